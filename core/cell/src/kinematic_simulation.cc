#include "cellmetry/cell/kinematic_simulation.h"

#include <cmath>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/job.h"

namespace cellmetry {
namespace {

const CylinderWorkspace& Workspace(const KinematicSimulationSpec& spec) {
  if (!spec.model->limits().workspace) {
    throw InputError({spec.model_file, 0, 0}, "the robot config has no workspace",
                     "Add workspace: {radius, z_min, z_max} to the robot config");
  }
  return *spec.model->limits().workspace;
}

Eigen::Vector3d InCylinder(const CylinderWorkspace& w, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double radius = w.radius_mm * std::sqrt(u(rng)), angle = 2 * M_PI * u(rng);
  return {radius * std::cos(angle), radius * std::sin(angle),
          w.z_min_mm + (w.z_max_mm - w.z_min_mm) * u(rng)};
}

Eigen::Vector3d OnCylinder(const CylinderWorkspace& w, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double side = 2 * M_PI * w.radius_mm * (w.z_max_mm - w.z_min_mm);
  const double disk = M_PI * w.radius_mm * w.radius_mm;
  const double pick = u(rng) * (side + 2 * disk);
  if (pick < side) {
    const double angle = 2 * M_PI * u(rng);
    return {w.radius_mm * std::cos(angle), w.radius_mm * std::sin(angle),
            w.z_min_mm + (w.z_max_mm - w.z_min_mm) * u(rng)};
  }
  Eigen::Vector3d p = InCylinder(w, rng);
  p.z() = pick < side + disk ? w.z_min_mm : w.z_max_mm;
  return p;
}

bool InView(const KinematicSimulationSpec& spec, const Eigen::Vector3d& marker_base) {
  const Eigen::Vector3d p = spec.T_base_cam_nominal.inverse() * marker_base;
  return p.z() > 0 && std::abs(p.x()) < p.z() * std::tan(spec.half_fov_rad.x()) &&
         std::abs(p.y()) < p.z() * std::tan(spec.half_fov_rad.y());
}

double Uniform(std::mt19937& rng, double half_width) {
  return std::uniform_real_distribution<double>(-half_width, half_width)(rng);
}

}  // namespace

std::string PoseSetName(PoseSet set) {
  switch (set) {
    case PoseSet::kCameraView: return "camera_view";
    case PoseSet::kUniformWorkspace: return "uniform_workspace";
    case PoseSet::kBoundaries: return "boundaries";
  }
  return "";
}

PoseSet ParsePoseSet(const ConfigNode& node) {
  const std::string name = node.AsString();
  for (PoseSet set : {PoseSet::kCameraView, PoseSet::kUniformWorkspace, PoseSet::kBoundaries}) {
    if (name == PoseSetName(set)) return set;
  }
  const std::string nearest =
      NearestWord(name, {"camera_view", "uniform_workspace", "boundaries"});
  throw node.Error("unknown pose set '" + name + "'",
                   (nearest.empty() ? "" : "Did you mean '" + nearest + "'? ") +
                       "Use camera_view, uniform_workspace or boundaries");
}

KinematicProblem SimulatedProblem(const KinematicSimulationSpec& spec, Formulation formulation,
                                  double noise_free_sigma_mm) {
  KinematicProblem problem;
  problem.robot = spec.robot;
  problem.target = spec.target;
  problem.camera = spec.camera;
  problem.model = spec.model;
  problem.model_parameters = spec.model->parameters();
  problem.marker_mm = spec.model->nominal_tool().t;
  problem.formulation = formulation;
  problem.sigma_mm = spec.sigma_mm.isZero() ? Eigen::Vector3d::Constant(noise_free_sigma_mm)
                                            : spec.sigma_mm;
  return problem;
}

void HoldParametersNamed(const std::string& suffix, KinematicProblem* problem) {
  for (auto& p : problem->model_parameters) {
    const auto& n = p.name;
    if (n.size() >= suffix.size() && n.compare(n.size() - suffix.size(), suffix.size(), suffix) == 0) {
      p.fixed = true;
    }
  }
}

KinematicState NominalState(const KinematicSimulationSpec& spec) {
  KinematicState state;
  state.T_base_cam = spec.T_base_cam_nominal;
  state.marker_mm = spec.model->nominal_tool().t;
  for (const auto& p : spec.model->parameters()) state.model_values.push_back(p.nominal);
  return state;
}

KinematicState DrawTruth(const KinematicSimulationSpec& spec, std::mt19937& rng) {
  KinematicState truth = NominalState(spec);
  const double increment = spec.model->limits().joint_increment_rad;
  const auto& params = spec.model->parameters();
  for (size_t i = 0; i < params.size(); ++i) {
    if (params[i].unit == "mm") {
      truth.model_values[i] += Uniform(rng, spec.errors.dimensions_mm);
    } else if (params[i].unit == "rad") {
      truth.model_values[i] += Uniform(rng, spec.errors.homing_increments * increment);
    }
  }
  Eigen::Vector3d rvec, shift;
  for (int k = 0; k < 3; ++k) {
    rvec[k] = Uniform(rng, spec.errors.camera_rad);
    shift[k] = Uniform(rng, spec.errors.camera_mm);
  }
  truth.T_base_cam = Pose{RotationFromRvec(rvec.data()) * spec.T_base_cam_nominal.R,
                          spec.T_base_cam_nominal.t + shift};
  return truth;
}

std::vector<std::vector<double>> MakePoseSet(const KinematicSimulationSpec& spec, PoseSet set,
                                             int count, std::mt19937& rng) {
  const CylinderWorkspace& w = Workspace(spec);
  const KinematicState nominal = NominalState(spec);
  std::vector<std::vector<double>> commands;
  for (int attempts = 0; static_cast<int>(commands.size()) < count; ++attempts) {
    if (attempts > 1000 * count) {
      throw InputError({spec.model_file, 0, 0},
                       "the pose set '" + PoseSetName(set) + "' has no reachable point in view",
                       "Check the workspace against the camera pose and field of view");
    }
    const Eigen::Vector3d flange = set == PoseSet::kBoundaries ? OnCylinder(w, rng)
                                                               : InCylinder(w, rng);
    if (set == PoseSet::kCameraView && !InView(spec, flange + nominal.marker_mm)) continue;
    std::vector<double> q(spec.model->num_joints());
    if (!spec.model->Inverse(flange.data(), nominal.model_values.data(), q.data())) continue;
    commands.push_back(q);
  }
  return commands;
}

Recording SimulateKinematic(const KinematicSimulationSpec& spec, const KinematicState& truth,
                            const std::vector<std::vector<double>>& commands, std::mt19937& rng) {
  Recording recording;
  recording.description = "simulated " + spec.robot + ", pose set " +
                          PoseSetName(spec.pose_set) + ", seed " + std::to_string(spec.seed);
  recording.robots[spec.robot] = spec.model->num_joints();
  recording.cameras = {spec.camera};
  recording.targets[spec.target] = spec.robot;
  std::normal_distribution<double> normal(0.0, 1.0);
  int id = 0;
  for (size_t pose = 0; pose < commands.size(); ++pose) {
    Eigen::Vector3d p_cam;
    if (!PredictInCamera(*spec.model, truth, commands[pose], &p_cam)) continue;
    for (int r = 0; r < spec.repeats; ++r, ++id) {
      Sample sample;
      sample.id = id;
      sample.robot = spec.robot;
      sample.pose = static_cast<int>(pose);
      sample.q = commands[pose];
      recording.samples.push_back(sample);
      Observation obs;
      obs.sample = id;
      obs.camera = spec.camera;
      obs.target = spec.target;
      for (int k = 0; k < 3; ++k) obs.position_mm[k] = p_cam[k] + spec.sigma_mm[k] * normal(rng);
      recording.observations.push_back(obs);
    }
  }
  return recording;
}

std::vector<SampleView> MarkerViews(const KinematicSimulationSpec& spec, const KinematicState& truth,
                                    const Recording& recording) {
  std::vector<SampleView> views;
  const Pose T_cam_base = truth.T_base_cam.inverse();
  for (const auto& sample : recording.samples) {
    Pose flange;
    if (!spec.model->Forward(sample.q.data(), truth.model_values.data(), &flange)) continue;
    const Pose T_base_marker{Eigen::Matrix3d::Identity(), flange * truth.marker_mm};
    views.push_back({sample.id, spec.camera, {{spec.target, T_cam_base * T_base_marker}}});
  }
  return views;
}

WorkcellTruth KinematicTruthRecord(const KinematicSimulationSpec& spec,
                                   const KinematicState& truth) {
  WorkcellTruth record;
  record.frames["camera"] = {"base", truth.T_base_cam};
  record.frames["marker"] = {spec.robot + ".flange", Pose{Eigen::Matrix3d::Identity(),
                                                          truth.marker_mm}};
  const auto& params = spec.model->parameters();
  for (size_t i = 0; i < params.size(); ++i) {
    record.model[spec.robot + ".model." + params[i].name] = truth.model_values[i];
  }
  return record;
}

PredictionError ComparePredictions(const RobotModel& model, const KinematicState& estimate,
                                   const KinematicState& truth,
                                   const std::vector<std::vector<double>>& commands) {
  PredictionError out;
  double sum = 0.0, sum2 = 0.0;
  for (const auto& q : commands) {
    Eigen::Vector3d a, b;
    if (!PredictInCamera(model, estimate, q, &a) || !PredictInCamera(model, truth, q, &b)) continue;
    const double d = (a - b).norm();
    sum += d;
    sum2 += d * d;
    out.max_mm = std::max(out.max_mm, d);
    ++out.points;
  }
  if (out.points > 0) {
    out.mean_mm = sum / out.points;
    out.rms_mm = std::sqrt(sum2 / out.points);
  }
  return out;
}

KinematicSimulationSpec LoadKinematicSimulation(const std::string& path, Registry& registry) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"simulation", "description", "seed", "robot", "camera", "target", "errors",
                   "noise", "poses", "images"});
  KinematicSimulationSpec spec;
  if (root.Has("images")) spec.images = root["images"];
  spec.seed = static_cast<unsigned>(root.GetInt("seed", 1));
  const ConfigNode robot = root["robot"];
  robot.ExpectKeys({"name", "model"});
  spec.robot = robot.GetString("name", spec.robot);
  spec.model_file = robot.ResolvePath(robot["model"].AsString());
  const ConfigNode model_config = ConfigNode::LoadFile(spec.model_file);
  spec.model = registry.CreateRobotModel(model_config["type"].AsString(), model_config);
  if (!spec.model->has_inverse()) {
    throw robot["model"].Error("this robot model has no position inverse kinematics",
                               "Kinematic simulations command points; use a delta arm config");
  }
  const ConfigNode camera = root["camera"];
  camera.ExpectKeys({"name", "xyz", "rvec", "half_fov_rad"});
  spec.camera = camera.GetString("name", spec.camera);
  spec.T_base_cam_nominal = ReadPose(camera);
  if (camera.Has("half_fov_rad")) {
    const auto v = camera["half_fov_rad"].AsDoubles(2);
    spec.half_fov_rad = Eigen::Vector2d(v[0], v[1]);
  }
  spec.target = root.GetString("target", spec.target);
  if (root.Has("errors")) {
    const ConfigNode e = root["errors"];
    e.ExpectKeys({"dimensions_mm", "homing_increments", "camera_mm", "camera_rad"});
    spec.errors.dimensions_mm = e.GetDouble("dimensions_mm", spec.errors.dimensions_mm);
    spec.errors.homing_increments = e.GetDouble("homing_increments", spec.errors.homing_increments);
    spec.errors.camera_mm = e.GetDouble("camera_mm", spec.errors.camera_mm);
    spec.errors.camera_rad = e.GetDouble("camera_rad", spec.errors.camera_rad);
  }
  if (root.Has("noise")) {
    const ConfigNode noise = root["noise"];
    noise.ExpectKeys({"position_mm"});
    const auto v = noise["position_mm"].AsDoubles(3);
    spec.sigma_mm = Eigen::Vector3d(v[0], v[1], v[2]);
  }
  const ConfigNode poses = root["poses"];
  poses.ExpectKeys({"set", "count", "repeats", "seed"});
  spec.pose_seed = static_cast<unsigned>(poses.GetInt("seed", static_cast<int>(spec.seed) + 1));
  spec.pose_set = ParsePoseSet(poses["set"]);
  spec.count = poses.GetInt("count", spec.count);
  spec.repeats = poses.GetInt("repeats", 1);
  if (spec.count < 1) throw poses["count"].Error("must be at least 1");
  if (spec.repeats < 1) throw poses["repeats"].Error("must be at least 1");
  return spec;
}

}  // namespace cellmetry
