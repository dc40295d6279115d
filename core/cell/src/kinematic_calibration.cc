#include "cellmetry/cell/kinematic_calibration.h"

#include <ceres/dynamic_autodiff_cost_function.h>

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "cellmetry/basics/error.h"
#include "cellmetry/model/frame_block.h"
#include "cellmetry/estimation/problem.h"
#include "cellmetry/basics/rigid_fit.h"
#include "kinematic_residuals.h"

namespace cellmetry {
namespace {

constexpr const char* kCamera = "camera";
constexpr const char* kMarker = "marker";
constexpr const char* kModel = "model";

std::vector<double> Values(const std::vector<Parameter>& params) {
  std::vector<double> values;
  for (const auto& p : params) values.push_back(p.nominal);
  return values;
}

// The assembled problem, with the rotation reference of the camera block.
struct Assembled {
  Problem problem;
  Eigen::Matrix3d R_ref_base_cam = Eigen::Matrix3d::Identity();
  int camera = 0, marker = 0, model = 0;
};

KinematicState ReadState(const Assembled& a) {
  KinematicState state;
  state.T_base_cam = FrameFromBlock(a.problem.values(a.camera), a.R_ref_base_cam);
  const double* m = a.problem.values(a.marker);
  state.marker_mm = Eigen::Vector3d(m[0], m[1], m[2]);
  const auto& params = a.problem.block_parameters(a.model);
  const double* v = a.problem.values(a.model);
  state.model_values.assign(v, v + params.size());
  return state;
}

// W with W^T W = (J Sigma J^T)^-1: whitens a joint residual by the propagated measurement noise.
Eigen::Matrix3d JointWhitening(const Eigen::Matrix3d& J, const Eigen::Vector3d& sigma_mm) {
  const Eigen::Matrix3d cov = J * sigma_mm.cwiseAbs2().asDiagonal() * J.transpose();
  const Eigen::Matrix3d L = Eigen::LLT<Eigen::Matrix3d>(cov).matrixL();
  return L.inverse();
}

std::unique_ptr<Assembled> Assemble(const KinematicProblem& spec,
                                    const std::vector<PointSample>& samples,
                                    const KinematicState& start, const Eigen::Vector3d& sigma) {
  auto a = std::make_unique<Assembled>();
  FrameBlockSpec camera;
  camera.start = Pose{Eigen::Matrix3d::Identity(), start.T_base_cam.t};
  camera.free = spec.camera_free;
  camera.description = "camera in the robot's base frame";
  a->R_ref_base_cam = start.T_base_cam.R;
  a->camera = a->problem.AddBlock(kCamera, FrameParameters(camera));
  std::vector<Parameter> marker;
  for (int i = 0; i < 3; ++i) {
    marker.push_back({std::string(1, "xyz"[i]), "mm", start.marker_mm[i], !spec.marker_free,
                      {}, {}, {}, "marker on the flange", {}});
  }
  a->marker = a->problem.AddBlock(kMarker, marker);
  std::vector<Parameter> model = spec.model_parameters;
  for (size_t i = 0; i < model.size(); ++i) model[i].nominal = start.model_values[i];
  a->model = a->problem.AddBlock(kModel, model);

  const RobotModel* robot = spec.model.get();
  for (const PointSample& s : samples) {
    ResidualInfo info;
    info.observation = s.observation;
    info.sample = s.sample;
    info.camera = spec.camera;
    info.target = spec.target;
    info.sigma = sigma;
    ceres::DynamicCostFunction* cost = nullptr;
    if (spec.formulation == Formulation::kForward) {
      cost = new ceres::DynamicAutoDiffCostFunction<ForwardPointResidual, kJetStride>(
          new ForwardPointResidual(robot, s.q, s.p_cam_mm, sigma, a->R_ref_base_cam));
    } else {
      Eigen::Vector3d q;
      Eigen::Matrix3d J;
      if (!InverseInCamera(*robot, start, s.p_cam_mm, &q, &J)) {
        const Eigen::Vector3d flange = start.T_base_cam * s.p_cam_mm - start.marker_mm;
        throw InputError(s.measured_at,
                         "the measured point is out of the arm's reach: " +
                             robot->InverseFailure(flange.data(), start.model_values.data()),
                         "Check the camera pose and marker offset, or remove this observation");
      }
      info.sigma = Eigen::Vector3d::Ones();  // rows are whitened joint errors
      cost = new ceres::DynamicAutoDiffCostFunction<InversePointResidual, kJetStride>(
          new InversePointResidual(robot, s.q, s.p_cam_mm, JointWhitening(J, sigma),
                                   a->R_ref_base_cam));
    }
    cost->AddParameterBlock(6);
    cost->AddParameterBlock(3);
    cost->AddParameterBlock(static_cast<int>(model.size()));
    cost->SetNumResiduals(3);
    a->problem.AddResidual(std::unique_ptr<ceres::CostFunction>(cost),
                           {a->camera, a->marker, a->model}, info);
  }
  a->problem.Build();
  return a;
}

// A command outside the robot config's joint limits cannot have been reached.
void CheckJointLimits(const RobotModel& model, const Sample& sample, const std::string& file) {
  const RobotLimits& limits = model.limits();
  for (size_t j = 0; j < limits.joint_min_rad.size() && j < sample.q.size(); ++j) {
    const double q = sample.q[j];
    if (q >= limits.joint_min_rad[j] && q <= limits.joint_max_rad[j]) continue;
    char text[160];
    std::snprintf(text, sizeof(text),
                  "unreachable command: q%zu = %.4f rad is outside the joint limits [%.4f, %.4f]",
                  j + 1, q, limits.joint_min_rad[j], limits.joint_max_rad[j]);
    throw InputError({file, sample.line, static_cast<int>(4 + j)}, text,
                     "Check the joint values (rad, not deg?) or the robot config's joint_limits");
  }
}


void CheckProblem(const KinematicProblem& spec, const std::vector<PointSample>& samples,
                  int num_free) {
  if (spec.formulation == Formulation::kInverse &&
      (!spec.model->has_inverse() || spec.model->num_joints() != 3)) {
    throw InputError({samples.empty() ? "" : samples.front().command_at.file, 0, 0},
                     "the inverse formulation needs a robot model with position "
                                 "inverse kinematics (3 joints); this one has none",
                     "Use formulation: forward");
  }
  if (static_cast<int>(samples.size()) < num_free) {
    throw InputError({samples.empty() ? "" : samples.front().command_at.file, 0, 0},
                     "the pose set has " + std::to_string(samples.size()) + " samples for " +
                         std::to_string(num_free) + " free parameters",
                     "Record at least " + std::to_string(num_free) +
                         " positions, or free fewer parameters");
  }
}

FrameEstimate CameraEstimate(const KinematicState& state, const Uncertainty& u) {
  FrameEstimate frame;
  frame.name = kCamera;
  frame.parent = "base";
  frame.pose = state.T_base_cam;
  for (int i = 0; i < 6; ++i) {
    const std::string name = std::string(kCamera) + "." + kFrameParameterNames[i];
    const auto it = std::find(u.names.begin(), u.names.end(), name);
    frame.held[i] = it == u.names.end();
    const double sigma = frame.held[i] ? 0.0 : u.sigma[it - u.names.begin()];
    (i < 3 ? frame.sigma_mm[i] : frame.sigma_rad[i - 3]) = sigma;
  }
  return frame;
}

double SigmaOf(const Uncertainty& u, const std::string& name) {
  const auto it = std::find(u.names.begin(), u.names.end(), name);
  return it == u.names.end() ? 0.0 : u.sigma[it - u.names.begin()];
}

void Describe(const KinematicProblem& spec, KinematicResult* result) {
  const Uncertainty& u = result->uncertainty;
  result->camera = CameraEstimate(result->state, u);
  for (int i = 0; i < 3; ++i) {
    result->marker_sigma_mm[i] = SigmaOf(u, std::string(kMarker) + "." + "xyz"[i]);
  }
  std::set<std::string> held;
  for (const auto& h : result->unidentifiable) held.insert(h.name);
  for (size_t i = 0; i < spec.model_parameters.size(); ++i) {
    const Parameter& p = spec.model_parameters[i];
    ScalarEstimate s;
    s.name = p.name;
    s.unit = p.unit;
    s.nominal = p.nominal;
    s.value = result->state.model_values[i];
    const std::string full = std::string(kModel) + "." + p.name;
    s.held = p.fixed || held.count(full) > 0;
    s.sigma = SigmaOf(u, full);
    result->model_parameters.push_back(s);
  }
}

// Per-axis RMS of the forward residuals, corrected for the fitted parameters.
Eigen::Vector3d SigmaFromResiduals(const std::vector<Eigen::Vector3d>& errors, int num_free) {
  const ResidualRms rms = RmsOf(errors);
  const int rows = 3 * rms.count;
  const double dof = rows > num_free ? std::sqrt(double(rows) / (rows - num_free)) : 1.0;
  return (rms.axis * dof).cwiseMax(1e-6);
}

}  // namespace

std::string FormulationName(Formulation formulation) {
  return formulation == Formulation::kForward ? "forward" : "inverse";
}

bool InverseInCamera(const RobotModel& model, const KinematicState& state,
                     const Eigen::Vector3d& p_cam, Eigen::Vector3d* q_out,
                     Eigen::Matrix3d* d_q_d_p_cam) {
  const Eigen::Vector3d flange = state.T_base_cam * p_cam - state.marker_mm;
  const std::vector<Jet> params(state.model_values.begin(), state.model_values.end());
  Jet position[3], q[3];
  for (int i = 0; i < 3; ++i) {
    position[i] = Jet(flange[i]);
    for (int k = 0; k < 3; ++k) position[i].v[k] = state.T_base_cam.R(i, k);  // d flange / d p_cam
  }
  if (!model.Inverse(position, params.data(), q)) return false;
  for (int i = 0; i < 3; ++i) {
    (*q_out)[i] = q[i].a;
    for (int k = 0; k < 3; ++k) (*d_q_d_p_cam)(i, k) = q[i].v[k];
  }
  return true;
}

bool PredictInCamera(const RobotModel& model, const KinematicState& state,
                     const std::vector<double>& q, Eigen::Vector3d* p_cam_mm) {
  Pose flange;
  if (!model.Forward(q.data(), state.model_values.data(), &flange)) return false;
  *p_cam_mm = state.T_base_cam.inverse() * (flange * state.marker_mm);
  return true;
}

std::vector<Eigen::Vector3d> PredictionErrors(const RobotModel& model, const KinematicState& state,
                                              const std::vector<PointSample>& samples) {
  std::vector<Eigen::Vector3d> errors;
  for (const PointSample& s : samples) {
    Eigen::Vector3d p;
    if (PredictInCamera(model, state, s.q, &p)) errors.push_back(p - s.p_cam_mm);
  }
  return errors;
}

std::vector<PointSample> CollectPointSamples(const KinematicProblem& problem,
                                             const Recording& recording) {
  const SourceLocation where{recording.folder + "/recording.yaml", 0, 0};
  const auto robot = recording.robots.find(problem.robot);
  if (robot == recording.robots.end()) {
    throw InputError(where, "no robot '" + problem.robot + "' in the recording",
                     "Name the robot as recording.yaml does");
  }
  if (robot->second != problem.model->num_joints()) {
    throw InputError(where, "robot '" + problem.robot + "' has " + std::to_string(robot->second) +
                                " joints in the recording but the model has " +
                                std::to_string(problem.model->num_joints()),
                     "Use the robot config that matches the recorded robot");
  }
  const auto target = recording.targets.find(problem.target);
  if (target == recording.targets.end() || target->second != problem.robot) {
    throw InputError(where, "no target '" + problem.target + "' carried by '" + problem.robot + "'",
                     "Name the marker as recording.yaml does ('on: " + problem.robot + "')");
  }
  if (!recording.HasCamera(problem.camera)) {
    throw InputError(where, "no camera '" + problem.camera + "' in the recording",
                     "Name the camera as recording.yaml does");
  }
  std::vector<PointSample> samples;
  for (size_t i = 0; i < recording.observations.size(); ++i) {
    const Observation& obs = recording.observations[i];
    if (obs.target != problem.target || obs.camera != problem.camera) continue;
    const Sample& sample = recording.samples[recording.SampleIndex(obs.sample)];
    CheckJointLimits(*problem.model, sample, recording.folder + "/samples.csv");
    samples.push_back({sample.id, static_cast<int>(i), sample.q, obs.position_mm,
                       {recording.folder + "/samples.csv", sample.line, 0},
                       {recording.folder + "/observations.csv", obs.line, 0}});
  }
  if (samples.empty()) {
    throw InputError({recording.folder + "/observations.csv", 0, 0},
                     "no observation of target '" + problem.target + "' by camera '" +
                         problem.camera + "'",
                     "Record the marker with that camera, or name the ones the observations use");
  }
  return samples;
}

CameraPoseFit EstimateCameraPose(const KinematicProblem& problem,
                                 const std::vector<PointSample>& samples) {
  std::vector<Eigen::Vector3d> from_cam, to_base;
  const std::vector<double> nominal = Values(problem.model_parameters);
  for (const PointSample& s : samples) {
    Pose flange;
    if (!problem.model->Forward(s.q.data(), nominal.data(), &flange)) continue;
    from_cam.push_back(s.p_cam_mm);
    to_base.push_back(flange * problem.marker_mm);
  }
  const auto fit = FitRigidTransform(from_cam, to_base);
  if (!fit) {
    throw InputError({samples.empty() ? "" : samples.front().measured_at.file, 0, 0},
                     "cannot place the camera: fewer than three usable marker positions, or all "
                     "on one line (" + std::to_string(from_cam.size()) + " usable)",
                     "Record the marker at three or more positions that span a plane");
  }
  CameraPoseFit out;
  out.T_base_cam = *fit;
  out.points = static_cast<int>(from_cam.size());
  double sum = 0.0;
  for (size_t i = 0; i < from_cam.size(); ++i) sum += (*fit * from_cam[i] - to_base[i]).squaredNorm();
  out.rms_mm = std::sqrt(sum / from_cam.size());
  return out;
}

KinematicResult CalibrateKinematics(const KinematicProblem& spec,
                                    const std::vector<PointSample>& samples,
                                    const SolverMaker& make_solver) {
  KinematicResult result;
  result.formulation = spec.formulation;
  result.samples = static_cast<int>(samples.size());
  KinematicState state;
  state.marker_mm = spec.marker_mm;
  state.model_values = Values(spec.model_parameters);
  for (const PointSample& s : samples) {
    Pose flange;
    if (!spec.model->Forward(s.q.data(), state.model_values.data(), &flange)) {
      throw InputError(s.command_at,
                       "the command has no pose: " +
                           spec.model->ForwardFailure(s.q.data(), state.model_values.data()),
                       "Check the joint values (rad) and the robot config, or remove this sample");
    }
  }
  if (spec.T_base_cam_start) {
    state.T_base_cam = *spec.T_base_cam_start;
  } else {
    result.closed_form_camera = EstimateCameraPose(spec, samples);
    state.T_base_cam = result.closed_form_camera.T_base_cam;
  }
  // Without a stated sigma, start from the closed-form fit's scatter and refit once estimated.
  const double guess = std::max(result.closed_form_camera.rms_mm / std::sqrt(3.0), 1e-3);
  result.sigma_mm = spec.sigma_mm.value_or(Eigen::Vector3d::Constant(guess));
  result.sigma_source = spec.sigma_mm ? "job" : "residuals of a first fit";
  // A second pass when sigma must come from the residuals. (The inverse formulation's weights come
  // from the start; 1 mm of dimension error moves them by ~0.1 %, which costs no measurable
  // efficiency: held-out error 1.03x the floor either way.)
  const int passes = spec.sigma_mm ? 1 : 2;

  std::unique_ptr<Assembled> assembled;
  std::set<std::string> held;
  for (int pass = 0; pass < passes; ++pass) {
    assembled = Assemble(spec, samples, state, result.sigma_mm);
    if (pass == 0) CheckProblem(spec, samples, assembled->problem.num_free());
    IdentifiedSolve solved = SolveHoldingUnidentifiable(
        &assembled->problem, spec.identifiability_tolerance, held, make_solver);
    for (const auto& u : solved.unidentifiable) held.insert(u.name);
    result.unidentifiable.insert(result.unidentifiable.end(), solved.unidentifiable.begin(),
                                 solved.unidentifiable.end());
    // Report the passes as one solve: iterations and time add up, costs span them.
    const SolverSummary first = result.solver;
    result.solver = solved.summary;
    if (pass > 0) {
      result.solver.iterations += first.iterations;
      result.solver.evaluations += first.evaluations;
      result.solver.time_s += first.time_s;
    }
    state = ReadState(*assembled);
    if (!spec.sigma_mm && pass == 0) {
      result.sigma_mm = SigmaFromResiduals(PredictionErrors(*spec.model, state, samples),
                                           assembled->problem.num_free());
    }
  }
  result.state = state;
  result.uncertainty = ComputeUncertainty(assembled->problem);
  result.strong_correlations = StrongCorrelations(result.uncertainty);
  result.weakly_identified = WeaklyIdentified(result.uncertainty, spec.weak_vif);
  if (!result.weakly_identified.empty()) {
    std::string names;
    for (const auto& w : result.weakly_identified) names += (names.empty() ? "" : ", ") + w.name;
    result.warnings.push_back("this data barely identifies " + names +
                              ": they move together; record positions that vary them "
                              "independently (other heights, the workspace's edges)");
  }
  result.position_rms = RmsOf(PredictionErrors(*spec.model, state, samples));
  Describe(spec, &result);
  if (result.uncertainty.reduced_chi2 > 4.0) {
    result.warnings.push_back("residuals are " +
                              std::to_string(std::sqrt(result.uncertainty.reduced_chi2)).substr(0, 4) +
                              "x the stated noise: the model leaves something out; uncertainties "
                              "were scaled up");
  }
  return result;
}

double PredictionErrorFloorMm(const KinematicProblem& problem,
                              const std::vector<PointSample>& design,
                              const std::vector<std::vector<double>>& validation,
                              const KinematicState& truth, const Eigen::Vector3d& sigma_mm,
                              const std::vector<UnidentifiableParameter>& held) {
  KinematicProblem forward = problem;
  forward.formulation = Formulation::kForward;
  std::set<std::string> names;
  for (const auto& h : held) names.insert(h.name);
  auto design_problem = Assemble(forward, design, truth, sigma_mm);
  HoldParameters(&design_problem->problem, names);
  Eigen::MatrixXd J;
  design_problem->problem.Evaluate(nullptr, nullptr, &J, false);

  std::vector<PointSample> points;
  for (const auto& q : validation) points.push_back({0, 0, q, Eigen::Vector3d::Zero(), {}, {}});
  auto prediction = Assemble(forward, points, truth, Eigen::Vector3d::Ones());
  HoldParameters(&prediction->problem, names);
  Eigen::MatrixXd G;
  prediction->problem.Evaluate(nullptr, nullptr, &G, false);

  // F^-1 through the SVD of J (a pseudo-inverse where F is singular: those directions do not
  // change any prediction, or they would have been found unidentifiable).
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeThinV);
  const Eigen::VectorXd s = svd.singularValues();
  Eigen::VectorXd inv_s = Eigen::VectorXd::Zero(s.size());
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (s[i] > 1e-12 * s[0]) inv_s[i] = 1.0 / s[i];
  }
  const Eigen::MatrixXd GV = G * svd.matrixV() * inv_s.asDiagonal();  // G F^-1 G^T = GV GV^T
  return std::sqrt(GV.squaredNorm() / std::max<size_t>(validation.size(), 1));
}

}  // namespace cellmetry
