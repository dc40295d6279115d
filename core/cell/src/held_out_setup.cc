// The held-out check in another setup (held_out_setup.h): register the new setup's frames with
// the calibrated geometry held, score the other poses, and predict each point's covariance.
#include "cellmetry/cell/held_out_setup.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/statistics.h"
#include "cellmetry/cell/joint_ranges.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_data.h"

namespace cellmetry {
namespace {

constexpr double kChiSquare3Dof95 = 7.8147;  // 95 % quantile of chi-square with 3 dof

std::vector<int> PosesInCaptureOrder(const Recording& recording) {
  std::vector<int> poses;
  std::set<int> seen;
  for (const Sample& s : recording.samples) {
    if (seen.insert(s.pose).second) poses.push_back(s.pose);
  }
  return poses;
}

// The recording with only the samples (and their observations) of `poses`.
Recording WithPoses(const Recording& recording, const std::set<int>& poses) {
  Recording out = recording;
  out.samples.clear();
  out.observations.clear();
  out.images.clear();
  std::set<int> samples;
  for (const Sample& s : recording.samples) {
    if (!poses.count(s.pose)) continue;
    out.samples.push_back(s);
    samples.insert(s.id);
  }
  for (const Observation& o : recording.observations) {
    if (samples.count(o.sample)) out.observations.push_back(o);
  }
  return out;
}

// `spec` with every robot's model held at `model` (robot -> values) and every effect at
// `effects` (none given: the effect left out), registering the frames the job frees and
// nothing more: no cross-validation, no camera left out, no inputs to consider.
WorkcellProblem RegistrationProblem(const WorkcellProblem& spec,
                                    const std::map<std::string, std::vector<double>>& model,
                                    const std::map<std::string, std::vector<double>>& effects) {
  WorkcellProblem registration = spec;
  for (WorkcellRobot& robot : registration.robots) {
    const std::vector<double>& values = model.at(robot.name);
    for (size_t i = 0; i < robot.model_parameters.size(); ++i) {
      robot.model_parameters[i].nominal = values[i];
      robot.model_parameters[i].fixed = true;
    }
  }
  registration.effects.clear();
  for (WorkcellEffect effect : spec.effects) {
    const auto values = effects.find(effect.name);
    if (values == effects.end()) continue;
    effect.held_values = values->second;
    registration.effects.push_back(effect);
  }
  registration.folds = 0;
  registration.leave_one_camera_out = false;
  registration.compare_camera_models = false;
  registration.uncertain_inputs = {};
  registration.warm_start.reset();
  return registration;
}

std::map<std::string, std::vector<double>> NominalModels(const WorkcellProblem& spec) {
  std::map<std::string, std::vector<double>> nominal;
  for (const WorkcellRobot& robot : spec.robots) {
    for (const Parameter& p : robot.model->parameters()) nominal[robot.name].push_back(p.nominal);
  }
  return nominal;
}

// The position rows of carried targets: prediction - measurement (mm, camera axes), the row
// offset in the problem's residuals and its sigma.
struct PositionRow {
  int sample = 0;
  int pose = 0;
  std::string camera, target;
  Eigen::Vector3d error_mm;
  int row = 0;
  Eigen::Vector3d sigma_mm;
};

std::vector<PositionRow> CarriedPositionRows(const AssembledWorkcell& assembled,
                                             const Eigen::VectorXd& r, const Recording& recording) {
  std::vector<PositionRow> rows;
  const Problem& problem = assembled.problem;
  const auto& infos = problem.residual_infos();
  for (size_t b = 0; b < assembled.labels.size(); ++b) {
    const ResidualInfo& info = infos[b];
    const MeasurementLabel& label = assembled.labels[b];
    if (info.kind != ResidualInfo::Kind::kPosition || !recording.IsCarried(label.target)) {
      continue;
    }
    const int row = problem.residual_rows()[b];
    rows.push_back({label.sample, label.pose, label.camera, label.target,
                    r.segment<3>(row).cwiseProduct(info.sigma), row, info.sigma});
  }
  return rows;
}

double RmsOf(const std::vector<PositionRow>& rows) {
  double sum = 0.0;
  for (const PositionRow& row : rows) sum += row.error_mm.squaredNorm();
  return rows.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(rows.size()));
}

// prediction - measurement of the carried targets at `estimate` on `poses` of `recording`.
std::vector<PositionRow> ScoredRows(const WorkcellProblem& spec, const Recording& recording,
                                    const NoiseModel& noise, const WorkcellEstimate& estimate,
                                    const std::set<int>& poses) {
  WorkcellProblem cartesian = spec;
  cartesian.residual = ResidualForm::kCartesian;
  const WorkcellData data = PrepareWorkcellData(cartesian, recording);
  auto assembled = AssembleWorkcell(cartesian, recording, data, noise, estimate, poses);
  Eigen::VectorXd r;
  if (!assembled->problem.EvaluateSparse(&r, nullptr)) {
    throw InputError({recording.folder, 0, 0}, "the calibrated model cannot place a held-out pose",
                     "Check that the held-out recording is of the same robot and joints");
  }
  return CarriedPositionRows(*assembled, r, recording);
}

// The calibration's covariance of the entries `names` (result.uncertainty order), each scaled
// from the model's sigma to the total sigma (the parts beyond the model's keep its correlations).
Eigen::MatrixXd CalibratedCovariance(const Uncertainty& u, const std::vector<std::string>& names) {
  std::map<std::string, Eigen::Index> index;
  for (size_t i = 0; i < u.names.size(); ++i) index[u.names[i]] = static_cast<Eigen::Index>(i);
  const Eigen::Index n = static_cast<Eigen::Index>(names.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(n);
  std::vector<Eigen::Index> at(static_cast<size_t>(n), -1);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto it = index.find(names[static_cast<size_t>(i)]);
    if (it == index.end()) continue;  // held in the calibration: no uncertainty of its own
    at[static_cast<size_t>(i)] = it->second;
    const double model_sigma = std::sqrt(std::max(u.covariance(it->second, it->second), 0.0));
    if (model_sigma > 0.0) scale[i] = u.sigma[it->second] / model_sigma;
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index k = 0; k < n; ++k) {
      const Eigen::Index a = at[static_cast<size_t>(i)], b = at[static_cast<size_t>(k)];
      if (a >= 0 && b >= 0) S(i, k) = u.covariance(a, b) * scale[i] * scale[k];
    }
  }
  return S;
}

Eigen::MatrixXd PseudoInverse(const Eigen::MatrixXd& symmetric) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(symmetric);
  const Eigen::VectorXd& values = eig.eigenvalues();
  const double largest = values.size() > 0 ? values.maxCoeff() : 0.0;
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(values.size());
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    if (values[i] > 1e-12 * largest) inverse[i] = 1.0 / values[i];
  }
  return eig.eigenvectors() * inverse.asDiagonal() * eig.eigenvectors().transpose();
}

// The joint covariance S of (theta, phi) over the problem's free columns (held_out_setup.h),
// from the registration rows' whitened Jacobian and residuals.
Eigen::MatrixXd JointCovariance(const Eigen::MatrixXd& J, double dispersion,
                                const std::vector<bool>& is_theta, const Eigen::MatrixXd& S_tt) {
  std::vector<Eigen::Index> theta, phi;
  for (size_t c = 0; c < is_theta.size(); ++c) {
    (is_theta[c] ? theta : phi).push_back(static_cast<Eigen::Index>(c));
  }
  const Eigen::MatrixXd J_theta = J(Eigen::all, theta), J_phi = J(Eigen::all, phi);
  const Eigen::MatrixXd info_phi_inverse = PseudoInverse(J_phi.transpose() * J_phi);
  const Eigen::MatrixXd A = -info_phi_inverse * J_phi.transpose() * J_theta;
  const Eigen::MatrixXd S_phi = A * S_tt * A.transpose() + info_phi_inverse * dispersion;
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(J.cols(), J.cols());
  S(theta, theta) = S_tt;
  S(theta, phi) = S_tt * A.transpose();
  S(phi, theta) = A * S_tt;
  S(phi, phi) = S_phi;
  return S;
}

// The registered result's uncertainty with S, the joint covariance of the calibrated entries and
// the registered frames, in place of the registration's own (which holds the entries exact):
// what a command compensated in the new setup is uncertain by.
Uncertainty JointUncertainty(const Uncertainty& registration,
                             const std::vector<FreeParameter>& columns, const Eigen::MatrixXd& S) {
  Uncertainty joint;
  for (const FreeParameter& f : columns) joint.names.push_back(f.name);
  joint.covariance = S;
  joint.sigma = S.diagonal().cwiseMax(0.0).cwiseSqrt();
  joint.correlation = CorrelationOf(S);
  joint.chi2 = registration.chi2;
  joint.dof = registration.dof;
  joint.reduced_chi2 = registration.reduced_chi2;
  joint.scale = registration.scale;
  joint.condition_number = registration.condition_number;
  return joint;
}

// Each scored point's predicted covariance (held_out_setup.h) and its normalized square. The
// rows are weighted by the registration's noise model: where sigma was estimated from residuals,
// the new setup's own scatter about the calibrated model (N), measured on its registration
// poses, which the scored points never enter; where the job states sigma, that sigma widened by
// the registration rows' reduced chi-square where it exceeds 1.
void PredictCovariances(const WorkcellProblem& spec, const WorkcellResult& result,
                        const Recording& held_out, const WorkcellResult& registered,
                        const std::set<int>& registration, const std::set<int>& scored,
                        HeldOutSetupScore* score, Uncertainty* joint) {
  // The calibration's free entries, free again (at their calibrated values) beside the frames.
  WorkcellProblem free = spec;
  free.residual = ResidualForm::kCartesian;
  for (WorkcellRobot& robot : free.robots) {
    const std::vector<double>& values = result.estimate.model.at(robot.name);
    for (size_t i = 0; i < robot.model_parameters.size(); ++i) {
      robot.model_parameters[i].nominal = values[i];
    }
  }
  const WorkcellData data = PrepareWorkcellData(free, held_out);
  auto assemble = [&](const std::set<int>& poses) {
    auto assembled =
        AssembleWorkcell(free, held_out, data, registered.noise, registered.estimate, poses);
    HoldParameters(&assembled->problem, HeldOf(result.unidentifiable));
    return assembled;
  };
  auto on_registration = assemble(registration);
  auto on_scored = assemble(scored);
  Eigen::MatrixXd J, G;
  Eigen::VectorXd r_registration, r_scored;
  if (!on_registration->problem.Evaluate(nullptr, &r_registration, &J, false) ||
      !on_scored->problem.Evaluate(nullptr, &r_scored, &G, false)) {
    throw InputError({held_out.folder, 0, 0}, "the calibrated model cannot place a held-out pose",
                     "Check that the held-out recording is of the same robot and joints");
  }

  const auto& free_columns = on_registration->problem.free_parameters();
  std::set<int> theta_blocks(on_registration->model_block.begin(),
                             on_registration->model_block.end());
  theta_blocks.insert(on_registration->effect_block.begin(), on_registration->effect_block.end());
  std::vector<bool> is_theta;
  std::vector<std::string> theta_names;
  for (const FreeParameter& f : free_columns) {
    is_theta.push_back(theta_blocks.count(f.block) > 0);
    if (is_theta.back()) theta_names.push_back(f.name);
  }
  // The registration rows' reduced chi-square about the calibrated model, where above 1: the
  // stated sigma too optimistic for this setup widens the frames' part and every point's own.
  const double dof =
      static_cast<double>(J.rows()) - static_cast<double>(J.cols() - theta_names.size());
  const double dispersion = dof > 0 ? std::max(r_registration.squaredNorm() / dof, 1.0) : 1.0;
  const Eigen::MatrixXd S = JointCovariance(J, dispersion, is_theta,
                                            CalibratedCovariance(result.uncertainty, theta_names));
  *joint = JointUncertainty(registered.uncertainty, free_columns, S);
  for (const PositionRow& row : CarriedPositionRows(*on_scored, r_scored, held_out)) {
    const Eigen::MatrixXd G_p = row.sigma_mm.asDiagonal() * G.middleRows(row.row, 3);
    HeldOutPoint point{row.sample, row.pose, row.camera, row.target, row.error_mm, {}, 0.0, false};
    point.covariance_mm2 = G_p * S * G_p.transpose();
    point.covariance_mm2.diagonal() += dispersion * row.sigma_mm.cwiseAbs2();
    point.normalized_squared = row.error_mm.dot(point.covariance_mm2.ldlt().solve(row.error_mm));
    score->points.push_back(point);
  }
}

std::vector<int> PoseOfEachPoint(const HeldOutSetupScore& score) {
  std::vector<int> poses;
  for (const HeldOutPoint& p : score.points) poses.push_back(p.pose);
  return poses;
}

void Summarize(HeldOutSetupScore* score) {
  const auto& points = score->points;
  if (points.empty()) return;
  double sum = 0.0, normalized = 0.0;
  int within = 0;
  std::vector<double> sigmas;
  for (const HeldOutPoint& p : points) {
    const double e = p.error_mm.norm();
    sum += e;
    score->max_mm = std::max(score->max_mm, e);
    normalized += p.normalized_squared / 3.0;
    if (p.normalized_squared <= kChiSquare3Dof95) ++within;
    sigmas.push_back(std::sqrt(p.covariance_mm2.trace()));
  }
  const double n = static_cast<double>(points.size());
  score->mean_mm = sum / n;
  const RmsEstimate rms = RmsWithStandardError(SquaredErrors(*score), PoseOfEachPoint(*score));
  score->rms_mm = rms.rms;
  score->rms_se_mm = rms.standard_error;
  score->mean_normalized = normalized / n;
  score->within_95 = within / n;
  score->median_sigma_mm = UpperMedian(&sigmas);
}

}  // namespace

std::vector<double> SquaredErrors(const HeldOutSetupScore& score) {
  std::vector<double> squared;
  for (const HeldOutPoint& p : score.points) squared.push_back(p.error_mm.squaredNorm());
  return squared;
}

double RmsGainStandardError(const HeldOutSetupScore& before, const HeldOutSetupScore& after) {
  if (before.points.size() != after.points.size()) {
    throw std::invalid_argument("RmsGainStandardError: scores of different points");
  }
  for (size_t i = 0; i < before.points.size(); ++i) {
    if (before.points[i].sample != after.points[i].sample ||
        before.points[i].target != after.points[i].target) {
      throw std::invalid_argument("RmsGainStandardError: scores of different points");
    }
  }
  return RmsDifferenceStandardError(SquaredErrors(before), SquaredErrors(after),
                                    PoseOfEachPoint(before));
}

std::vector<int> SelectRegistrationPoses(const Recording& recording,
                                         const RegistrationPoses& register_on,
                                         const SourceLocation& where) {
  const std::vector<int> all = PosesInCaptureOrder(recording);
  std::vector<int> chosen;
  if (register_on.first > 0) {
    chosen.assign(all.begin(), all.begin() + std::min<size_t>(all.size(), register_on.first));
  } else if (register_on.every > 0) {
    for (size_t i = 0; i < all.size(); i += static_cast<size_t>(register_on.every)) {
      chosen.push_back(all[i]);
    }
  } else {
    const std::set<int> present(all.begin(), all.end());
    for (int pose : register_on.poses) {
      if (!present.count(pose)) {
        throw InputError(where,
                         "register_on: no pose " + std::to_string(pose) + " in " + recording.folder,
                         "Name pose ids as the recording's samples.csv has them");
      }
    }
    for (int pose : all) {
      if (std::count(register_on.poses.begin(), register_on.poses.end(), pose)) {
        chosen.push_back(pose);
      }
    }
  }
  if (chosen.size() >= all.size()) {
    throw InputError(where, "register_on leaves no pose of " + recording.folder + " to score",
                     "Register on fewer poses (a few dozen of hundreds is usual)");
  }
  return chosen;
}

HeldOutSetupScore ScoreHeldOutSetup(const WorkcellProblem& spec, const WorkcellResult& result,
                                    const Recording& calibration, const Recording& held_out,
                                    const std::vector<int>& poses, const SolverMaker& make_solver) {
  HeldOutSetupScore score;
  score.recording = held_out.folder;
  score.registration_poses = poses;
  const std::set<int> registration(poses.begin(), poses.end());
  std::set<int> scored;
  for (int pose : PosesInCaptureOrder(held_out)) {
    if (!registration.count(pose)) scored.insert(pose);
  }
  score.scored_poses = static_cast<int>(scored.size());
  const Recording registration_recording = WithPoses(held_out, registration);

  // The calibrated geometry, registered; then the nominal one, registered the same way.
  const WorkcellProblem calibrated =
      RegistrationProblem(spec, result.estimate.model, result.estimate.effects);
  const WorkcellResult registered =
      IdentifyWorkcell(calibrated, registration_recording, make_solver);
  const WorkcellProblem nominal = RegistrationProblem(spec, NominalModels(spec), {});
  const WorkcellResult nominal_registered =
      IdentifyWorkcell(nominal, registration_recording, make_solver);
  score.nominal_rms_mm =
      RmsOf(ScoredRows(nominal, held_out, result.noise, nominal_registered.estimate, scored));
  score.registration_rms_mm =
      RmsOf(ScoredRows(calibrated, held_out, result.noise, registered.estimate, registration));

  auto for_compensation = std::make_shared<WorkcellResult>(registered);
  // Its geometry was measured where the calibration's poses went, not the registration's.
  for (RobotModelRecord& record : for_compensation->robot_models) {
    for (const RobotModelRecord& calibrated : result.robot_models) {
      if (calibrated.robot == record.robot) record.joint_ranges_rad = calibrated.joint_ranges_rad;
    }
  }
  PredictCovariances(spec, result, held_out, registered, registration, scored, &score,
                     &for_compensation->uncertainty);
  Summarize(&score);
  MarkBeyondCalibration(calibration, held_out, &score);
  // The calibrated entries read as the calibration has them: its values, with their sigma in S.
  const Uncertainty& joint = for_compensation->uncertainty;
  for (ScalarEstimate& p : for_compensation->model_parameters) {
    const auto it = std::find(joint.names.begin(), joint.names.end(), p.name);
    if (it == joint.names.end()) continue;
    p.held = false;
    p.sigma = p.sigma_statistical = joint.sigma[it - joint.names.begin()];
  }
  score.registered = for_compensation;
  return score;
}

}  // namespace cellmetry
