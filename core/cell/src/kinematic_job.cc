#include "cellmetry/cell/kinematic_job.h"

#include <filesystem>

#include "cellmetry/cell/job.h"

namespace cellmetry {
namespace {

// `robot: {name, model, free}`: the model from its config; `free:` lists parameter names or all.
void ReadRobot(const ConfigNode& node, Registry& registry, KinematicProblem* problem) {
  node.ExpectKeys({"name", "model", "free"});
  problem->robot = node["name"].AsString();
  const std::string file = node.ResolvePath(node["model"].AsString());
  if (!std::filesystem::exists(file)) {
    throw node["model"].Error("robot config '" + file + "' not found",
                              "Give a path relative to the job file");
  }
  const ConfigNode config = ConfigNode::LoadFile(file);
  problem->model = registry.CreateRobotModel(config["type"].AsString(), config);
  problem->model_parameters = problem->model->parameters();
  problem->marker_mm = problem->model->nominal_tool().t;
  for (auto& p : problem->model_parameters) p.fixed = true;
  if (!node.Has("free")) return;
  const ConfigNode free = node["free"];
  for (const auto& name : free.AsStrings()) {
    if (name == "all") {
      for (auto& p : problem->model_parameters) p.fixed = false;
      continue;
    }
    const int index = FindParameter(problem->model_parameters, name);
    if (index < 0) {
      std::vector<std::string> known;
      for (const auto& p : problem->model_parameters) known.push_back(p.name);
      const std::string nearest = NearestWord(name, known);
      throw free.Error("the robot model has no parameter '" + name + "'",
                       nearest.empty() ? "Run 'cellmetry plugins' to list its parameters"
                                       : "Did you mean '" + nearest + "'?");
    }
    problem->model_parameters[index].fixed = false;
  }
}

void ReadCamera(const ConfigNode& node, bool pose_required, KinematicProblem* problem) {
  node.ExpectKeys({"name", "xyz", "rvec", "free"});
  problem->camera = node["name"].AsString();
  if (node.Has("xyz") || node.Has("rvec")) {
    problem->T_base_cam_start = ReadPose(node);
  } else if (pose_required) {
    throw node.Error("the camera pose is needed here",
                     "Give camera: {xyz: [mm], rvec: [rad]} from a calibration result");
  }
  problem->camera_free = ReadFreeFlags(node, problem->camera_free);
}

Eigen::Vector3d ReadSigma(const ConfigNode& noise) {
  noise.ExpectKeys({"position_mm"});
  const auto v = noise["position_mm"].AsDoubles(3);
  const Eigen::Vector3d sigma(v[0], v[1], v[2]);
  if (!(sigma.array() > 0).all()) {
    throw noise["position_mm"].Error("every sigma must be positive", "Give x, y, depth in mm");
  }
  return sigma;
}

std::string Output(const ConfigNode& root, const std::string& path) {
  return root.Has("output") ? root.ResolvePath(root["output"].AsString())
                            : "results/" + std::filesystem::path(path).stem().string();
}

}  // namespace

KinematicJob LoadKinematicJob(const std::string& path, Registry& registry) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"job", "description", "recording", "validation_recording", "output", "robot",
                   "camera", "target", "marker", "formulation", "noise", "solver",
                   "identifiability_tolerance", "weak_vif"});
  KinematicJob job;
  job.file = path;
  job.recording = ReadRecordingPath(root["recording"]);
  if (root.Has("validation_recording")) {
    job.validation_recording = ReadRecordingPath(root["validation_recording"]);
  }
  job.output = Output(root, path);
  KinematicProblem& problem = job.problem;
  ReadRobot(root["robot"], registry, &problem);
  ReadCamera(root["camera"], /*pose_required=*/false, &problem);
  problem.target = root["target"].AsString();
  if (root.Has("marker")) {
    const ConfigNode marker = root["marker"];
    marker.ExpectKeys({"xyz", "free"});
    if (marker.Has("xyz")) problem.marker_mm = ReadPose(marker).t;
    problem.marker_free = marker.GetBool("free", false);
  }
  const std::string formulation = root.GetString("formulation", "forward");
  if (formulation == "inverse") {
    problem.formulation = Formulation::kInverse;
  } else if (formulation != "forward") {
    throw root["formulation"].Error("unknown formulation '" + formulation + "'",
                                    "Use forward (Cartesian residual) or inverse (joint space)");
  }
  if (problem.formulation == Formulation::kInverse && !problem.model->has_inverse()) {
    throw root["formulation"].Error("this robot model has no position inverse kinematics",
                                    "Use formulation: forward");
  }
  if (root.Has("noise")) problem.sigma_mm = ReadSigma(root["noise"]);
  problem.identifiability_tolerance =
      root.GetDouble("identifiability_tolerance", problem.identifiability_tolerance);
  problem.weak_vif = root.GetDouble("weak_vif", problem.weak_vif);
  const ConfigNode solver = root["solver"];
  job.solver_type = solver["type"].AsString();
  job.solver_config = solver;
  registry.CreateSolver(job.solver_type, solver);  // a bad option fails before any work
  return job;
}

HomingJob LoadHomingJob(const std::string& path, Registry& registry) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"job", "description", "recording", "output", "robot", "camera", "target",
                   "noise", "homing"});
  HomingJob job;
  job.file = path;
  job.recording = ReadRecordingPath(root["recording"]);
  job.output = Output(root, path);
  ReadRobot(root["robot"], registry, &job.problem);
  if (!job.problem.model->has_inverse()) {
    throw root["robot"]["model"].Error("homing needs a robot model with inverse kinematics",
                                       "Use a delta arm config");
  }
  ReadCamera(root["camera"], /*pose_required=*/true, &job.problem);
  job.problem.target = root["target"].AsString();
  job.sigma_mm = ReadSigma(root["noise"]);
  if (root.Has("homing")) {
    const ConfigNode h = root["homing"];
    h.ExpectKeys({"n_sigma", "target_width_increments", "min_positions", "max_reruns"});
    job.options.n_sigma = h.GetDouble("n_sigma", job.options.n_sigma);
    job.options.target_width_increments =
        h.GetDouble("target_width_increments", job.options.target_width_increments);
    job.options.min_positions = h.GetInt("min_positions", job.options.min_positions);
    job.options.max_reruns = h.GetInt("max_reruns", job.options.max_reruns);
    if (job.options.min_positions < 2) {
      throw h["min_positions"].Error("must be at least 2", "An interval needs company");
    }
  }
  return job;
}

}  // namespace cellmetry
