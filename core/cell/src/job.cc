#include "cellmetry/cell/job.h"

#include <algorithm>

#include <filesystem>

namespace cellmetry {
namespace {

WorkcellRobot ReadRobot(const std::string& name, const ConfigNode& node, Registry& registry) {
  node.ExpectKeys({"model", "base", "tools", "free_model", "effects"});
  WorkcellRobot robot;
  robot.name = name;
  robot.model_file = node.ResolvePath(node["model"].AsString());
  if (!std::filesystem::exists(robot.model_file)) {
    throw node["model"].Error("robot config '" + robot.model_file + "' not found",
                              "Give a path relative to the job file");
  }
  const ConfigNode model_config = ConfigNode::LoadFile(robot.model_file);
  const std::string type = model_config["type"].AsString();
  robot.model = registry.CreateRobotModel(type, model_config);
  robot.model_parameters = robot.model->parameters();
  for (auto& p : robot.model_parameters) p.fixed = true;  // the job frees what it identifies
  if (node.Has("free_model")) {
    const ConfigNode free = node["free_model"];
    for (const auto& entry : free.AsStrings()) {
      if (entry == "all") {
        for (auto& p : robot.model_parameters) p.fixed = false;
        continue;
      }
      const int index = FindParameter(robot.model_parameters, entry);
      if (index < 0) {
        std::vector<std::string> known;
        for (const auto& p : robot.model_parameters) known.push_back(p.name);
        const std::string nearest = NearestWord(entry, known);
        throw free.Error("robot model '" + type + "' has no parameter '" + entry + "'",
                         nearest.empty() ? "Run 'cellmetry plugins' to list its parameters"
                                         : "Did you mean '" + nearest + "'?");
      }
      robot.model_parameters[index].fixed = false;
    }
  }

  robot.base.free.fill(true);
  robot.base.description = "base of " + name + " in the world";
  if (node.Has("base")) {
    const ConfigNode base = node["base"];
    base.ExpectKeys({"free", "start"});
    robot.base.free = ReadFreeFlags(base, robot.base.free);
    if (base.Has("start")) robot.base_start = ReadPose(base["start"]);
  }
  if (robot.base_start) robot.base.start = *robot.base_start;

  const ConfigNode tools = node["tools"];
  for (const auto& target : tools.Keys()) {
    WorkcellTool t;
    t.target = target;
    t.flange_tool.free = {true, true, true, false, false, false};
    t.flange_tool.description = "target '" + target + "' on the flange of " + name;
    // `target:` with no value is allowed: position free, starting at the flange.
    if (const auto tool = tools.Optional(target)) {
      tool->ExpectKeys({"xyz", "rvec", "free"});
      t.flange_tool.start = ReadPose(*tool);
      t.flange_tool.free = ReadFreeFlags(*tool, t.flange_tool.free);
    }
    robot.tools.push_back(t);
  }
  return robot;
}

NoiseSpec ReadNoise(const ConfigNode& node) {
  node.ExpectKeys({"floor_mm", "floor_rad", "cameras"});
  NoiseSpec noise;
  noise.floor_mm = node.GetDouble("floor_mm", noise.floor_mm);
  noise.floor_rad = node.GetDouble("floor_rad", noise.floor_rad);
  if (node.Has("cameras")) {
    const ConfigNode cameras = node["cameras"];
    for (const auto& camera : cameras.Keys()) {
      const ConfigNode c = cameras[camera];
      c.ExpectKeys({"position_mm", "rotation_rad"});
      if (c.Has("position_mm")) {
        const auto v = c["position_mm"].AsDoubles(3);
        noise.position_sigma_mm[camera] = Eigen::Vector3d(v[0], v[1], v[2]);
      }
      if (c.Has("rotation_rad")) {
        const auto v = c["rotation_rad"].AsDoubles(3);
        noise.rotation_sigma_rad[camera] = Eigen::Vector3d(v[0], v[1], v[2]);
      }
    }
  }
  return noise;
}

}  // namespace

// `effects:` (effect.h): a list of effect blocks {type: <plugin>, <options>} in `robot`'s chain,
// named "<prefix>.<type>" (the robot's name, or "camera" for the measurement effects).
void AddEffects(const ConfigNode& list, const std::string& robot, const std::string& prefix,
                Registry& registry, WorkcellProblem* problem) {
  const auto owner = std::find_if(problem->robots.begin(), problem->robots.end(),
                                  [&](const WorkcellRobot& r) { return r.name == robot; });
  for (const auto& config : list.Elements()) {
    WorkcellEffect e;
    e.robot = robot;
    e.effect = registry.CreateEffect(config["type"].AsString(), config, *owner->model);
    e.name = prefix + "." + config["type"].AsString();
    for (int k = 2; std::any_of(problem->effects.begin(), problem->effects.end(),
                                [&](const WorkcellEffect& x) { return x.name == e.name; });
         ++k) {
      e.name = prefix + "." + config["type"].AsString() + "_" + std::to_string(k);
    }
    problem->effects.push_back(e);
  }
}

WorkcellJob LoadWorkcellJob(const std::string& path, Registry& registry,
                            bool recording_must_exist) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"job", "description", "recording", "output", "plugin_paths", "world_target",
                   "camera_model", "use_tool_rotation", "robots", "noise", "solver",
                   "validation", "identifiability_tolerance", "effects", "gravity_base",
                   "diagnosis"});
  WorkcellJob job;
  job.file = path;
  const std::string kind = root["job"].AsString();
  if (kind != "workcell") {
    throw root["job"].Error("unknown job kind '" + kind + "'", "This version runs: workcell");
  }
  if (root.Has("plugin_paths")) {
    for (const auto& folder : root["plugin_paths"].AsStrings()) {
      registry.LoadFolder(root.ResolvePath(folder));
    }
  }
  job.recording = recording_must_exist
                      ? ReadRecordingPath(root["recording"])
                      : root["recording"].ResolvePath(root["recording"].AsString());
  const std::string stem = std::filesystem::path(path).stem().string();
  job.output = root.Has("output") ? root.ResolvePath(root["output"].AsString())
                                  : "results/" + stem;
  WorkcellProblem& problem = job.problem;
  problem.world_target = root.GetString("world_target", problem.world_target);
  const std::string camera_model = root.GetString("camera_model", "static_cameras");
  if (camera_model == "static_cameras") {
    problem.camera_model = CameraModel::kStaticCameras;
  } else if (camera_model == "per_frame") {
    problem.camera_model = CameraModel::kPerFrame;
  } else {
    throw root["camera_model"].Error("unknown camera model '" + camera_model + "'",
                                     "Use static_cameras or per_frame");
  }
  problem.use_tool_rotation = root.GetBool("use_tool_rotation", false);
  problem.identifiability_tolerance =
      root.GetDouble("identifiability_tolerance", problem.identifiability_tolerance);
  job.locations["world_target"] =
      root.Has("world_target") ? root["world_target"].location() : root.location();
  const ConfigNode robots = root["robots"];
  for (const auto& name : robots.Keys()) {
    const ConfigNode robot = robots[name];
    problem.robots.push_back(ReadRobot(name, robot, registry));
    job.locations["robots." + name] = robot.location();
    for (const auto& target : robot["tools"].Keys()) {
      const auto tool = robot["tools"].Optional(target);
      job.locations["robots." + name + ".tools." + target] =
          tool ? tool->location() : robot["tools"].location();
    }
  }
  for (const auto& name : robots.Keys()) {
    if (robots[name].Has("effects")) {
      AddEffects(robots[name]["effects"], name, name, registry, &problem);
    }
  }
  if (root.Has("effects")) {
    AddEffects(root["effects"], problem.robots.front().name, "camera", registry, &problem);
    for (const auto& e : problem.effects) {
      if (e.name.rfind("camera.", 0) == 0 && e.effect->stage() != EffectStage::kMeasurement) {
        throw root["effects"].Error("'" + e.name + "' acts on a robot's joints or flange",
                                    "List it under that robot's effects:");
      }
    }
  }
  if (root.Has("gravity_base")) {
    const auto g = root["gravity_base"].AsDoubles(3);
    problem.gravity_base = Eigen::Vector3d(g[0], g[1], g[2]);
  }
  if (root.Has("noise")) problem.noise = ReadNoise(root["noise"]);
  if (root.Has("validation")) {
    const ConfigNode v = root["validation"];
    v.ExpectKeys({"folds", "seed", "compare_camera_models"});
    problem.folds = v.GetInt("folds", problem.folds);
    problem.seed = static_cast<unsigned>(v.GetInt("seed", 1));
    problem.compare_camera_models = v.GetBool("compare_camera_models", false);
  }
  const ConfigNode solver = root["solver"];
  job.solver_type = solver["type"].AsString();
  job.solver_config = solver;
  // Build one solver now so a bad option fails before any work is done.
  registry.CreateSolver(job.solver_type, solver);
  return job;
}

SourceLocation WorkcellJob::Where(const std::string& key) const {
  const auto it = locations.find(key);
  return it == locations.end() ? SourceLocation{file, 0, 0} : it->second;
}

void ValidateJobAgainstRecording(const WorkcellJob& job, const Recording& recording) {
  const auto world = recording.targets.find(job.problem.world_target);
  if (world == recording.targets.end() || world->second != kWorldCarrier) {
    throw InputError(job.Where("world_target"), "the recording has no world-fixed target '" +
                                job.problem.world_target + "'",
                     "Set 'world_target:' to a target that recording.yaml puts 'on: world'");
  }
  for (const auto& robot : job.problem.robots) {
    const auto joints = recording.robots.find(robot.name);
    if (joints == recording.robots.end()) {
      throw InputError(job.Where("robots." + robot.name),
                       "robot '" + robot.name + "' is not in the recording " +
                                  recording.folder,
                       "Name the robot as recording.yaml does");
    }
    if (joints->second != robot.model->num_joints()) {
      throw InputError(job.Where("robots." + robot.name), "robot '" + robot.name + "' has " +
                                  std::to_string(joints->second) + " joints in the recording but " +
                                  std::to_string(robot.model->num_joints()) + " in " +
                                  robot.model_file,
                       "Use the robot config that matches the recorded robot");
    }
    for (const auto& tool : robot.tools) {
      const auto target = recording.targets.find(tool.target);
      if (target == recording.targets.end() || target->second != robot.name) {
        throw InputError(job.Where("robots." + robot.name + ".tools." + tool.target),
                         "target '" + tool.target + "' is not carried by robot '" +
                                    robot.name + "' in the recording",
                         "List under 'tools:' the targets recording.yaml puts 'on: " +
                             robot.name + "'");
      }
    }
  }
}

}  // namespace cellmetry
