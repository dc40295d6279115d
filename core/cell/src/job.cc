// The one job reader (job.h): every cell, from a multi-robot workcell to a delta arm.
#include "cellmetry/cell/job.h"

#include <algorithm>

#include <filesystem>
#include <map>
#include <set>

#include "angle_unit_check.h"
#include "length_scale_check.h"
#include "robot_config.h"

namespace cellmetry {
namespace {

// `free_model: [names] | all`: which of the model's parameters the job identifies.
void ReadFreeModel(const ConfigNode& free, const std::string& type, WorkcellRobot* robot) {
  std::set<std::string> seen;
  for (const auto& entry : free.AsStrings()) {
    if (!seen.insert(entry).second) {
      throw free.Error("'" + entry + "' appears twice in free_model", "Name each entry once");
    }
    if (entry == "all") {
      for (auto& p : robot->model_parameters) p.fixed = false;
      continue;
    }
    const int index = FindParameter(robot->model_parameters, entry);
    if (index < 0) {
      std::vector<std::string> known;
      for (const auto& p : robot->model_parameters) known.push_back(p.name);
      const std::string nearest = NearestWord(entry, known);
      throw free.Error("robot model '" + type + "' has no parameter '" + entry + "'",
                       nearest.empty() ? "Run 'cellmetry plugins' to list its parameters"
                                       : "Did you mean '" + nearest + "'?");
    }
    robot->model_parameters[index].fixed = false;
  }
}

// `tools: {<target>: {xyz, rvec, free}}`; a target with no value starts at the model's nominal
// tool (the flange for a serial arm, the marker offset of a delta's config), position free.
void ReadTools(const ConfigNode& tools, WorkcellRobot* robot) {
  for (const auto& target : tools.Keys()) {
    WorkcellTool t;
    t.target = target;
    t.flange_tool.start = robot->model->nominal_tool();
    t.flange_tool.free = {true, true, true, false, false, false};
    t.flange_tool.description = "target '" + target + "' on the flange of " + robot->name;
    if (const auto tool = tools.Optional(target)) {
      tool->ExpectKeys({"xyz", "rvec", "free"});
      if (tool->Has("xyz") || tool->Has("rvec")) t.flange_tool.start = ReadPose(*tool);
      t.flange_tool.free = ReadFreeFlags(*tool, t.flange_tool.free);
    }
    robot->tools.push_back(t);
  }
}

// `cameras: {<camera>: {xyz, rvec, free}}`: cameras riding on the flange (eye in hand), each a
// frame T_flange_camera named "<robot>.<camera>"; every entry free and, without xyz/rvec, a
// closed-form start (hand_eye_start.h).
void ReadMountedCameras(const ConfigNode& cameras, WorkcellRobot* robot) {
  for (const auto& camera : cameras.Keys()) {
    WorkcellTool t;
    t.camera = camera;
    t.target = robot->name + "." + camera;
    t.flange_tool.free.fill(true);
    t.flange_tool.description = "camera '" + camera + "' on the flange of " + robot->name;
    if (const auto node = cameras.Optional(camera)) {
      node->ExpectKeys({"xyz", "rvec", "free"});
      if (node->Has("xyz") || node->Has("rvec")) {
        t.flange_tool.start = ReadPose(*node);
        t.start_given = true;
      }
      t.flange_tool.free = ReadFreeFlags(*node, t.flange_tool.free);
    }
    robot->tools.push_back(t);
  }
}

// `base: {free, start}`. Where it is the world (the first robot's, without a world target):
// held, at its start.
void ReadBase(const ConfigNode& node, bool world_is_base, WorkcellRobot* robot) {
  robot->base.free.fill(!world_is_base);
  robot->base.description = "base of " + robot->name + " in the world";
  if (world_is_base) robot->base_start = Pose::Identity();
  if (!node.Has("base")) {
    if (robot->base_start) robot->base.start = *robot->base_start;
    return;
  }
  const ConfigNode base = node["base"];
  base.ExpectKeys({"free", "start", "level"});
  robot->base.free = ReadFreeFlags(base, robot->base.free);
  if (base.Has("start")) robot->base_start = ReadPose(base["start"]);
  if (base.Has("level")) {
    const ConfigNode level = base["level"];
    level.ExpectKeys({"sigma_rad"});
    if (!level.Has("sigma_rad")) {
      throw level.Error("level: needs sigma_rad",
                        "Say how far from level the base may stand, "
                        "e.g. level: {sigma_rad: 0.003}");
    }
    robot->level_sigma_rad = level.GetDoubleIn(
        "sigma_rad", 0.0, 1e-9, 0.5,
        "How far from level the base may stand, 1 sigma in rad: 0.003 is a table levelled "
        "by eye");
    if (!robot->base.free[3] || !robot->base.free[4]) {
      throw level.Error("a level prior needs the base's rotation about x and y free",
                        "Free them (free: all), or drop level: to hold the rotation instead");
    }
  }
  if (world_is_base &&
      std::find(robot->base.free.begin(), robot->base.free.end(), true) != robot->base.free.end()) {
    throw base["free"].Error("without a world target the robot's base is the world frame",
                             "Hold the base (free: none), or name a world_target");
  }
  if (robot->base_start) robot->base.start = *robot->base_start;
}

WorkcellRobot ReadRobot(const std::string& name, const ConfigNode& node, bool world_is_base,
                        Registry& registry) {
  node.ExpectKeys({"model", "base", "tools", "cameras", "free_model", "effects"});
  WorkcellRobot robot;
  robot.name = name;
  const RobotConfig config = ReadRobotConfig(node, registry);
  robot.model_file = config.file;
  robot.model_config = config.text;
  robot.model = config.model;
  robot.model_parameters = robot.model->parameters();
  for (auto& p : robot.model_parameters) p.fixed = true;  // the job frees what it identifies
  if (node.Has("free_model")) ReadFreeModel(node["free_model"], config.type, &robot);
  ReadBase(node, world_is_base, &robot);
  if (!node.Has("tools") && !node.Has("cameras")) {
    throw node.Error("robot '" + name + "' has nothing on its flange to identify",
                     "List the targets it carries under 'tools:', or the cameras riding on it "
                     "under 'cameras:' (eye in hand)");
  }
  if (node.Has("tools")) ReadTools(node["tools"], &robot);
  if (node.Has("cameras")) ReadMountedCameras(node["cameras"], &robot);
  return robot;
}

// `cameras: {<name>: {xyz, rvec, free, use}}`: a start (none: closed form), the free entries,
// and whether its observations are used at all.
std::map<std::string, WorkcellCamera> ReadCameras(const ConfigNode& cameras) {
  std::map<std::string, WorkcellCamera> out;
  for (const auto& name : cameras.Keys()) {
    WorkcellCamera camera;
    if (const auto node = cameras.Optional(name)) {
      node->ExpectKeys({"xyz", "rvec", "free", "use"});
      if (node->Has("xyz") || node->Has("rvec")) camera.start = ReadPose(*node);
      camera.free = ReadFreeFlags(*node, camera.free);
      camera.use = node->GetBool("use", true);
    }
    out[name] = camera;
  }
  return out;
}

NoiseSpec ReadNoise(const ConfigNode& node) {
  node.ExpectKeys({"floor_mm", "floor_rad", "cameras"});
  NoiseSpec noise;
  noise.floor_mm = node.GetDoubleIn("floor_mm", noise.floor_mm, 0.0, 1e3,
                                    "A floor is the smallest sigma any camera gets, in mm");
  noise.floor_rad = node.GetDoubleIn("floor_rad", noise.floor_rad, 0.0, 1.0,
                                     "A floor is the smallest sigma any camera gets, in rad");
  if (node.Has("cameras")) {
    const ConfigNode cameras = node["cameras"];
    for (const auto& camera : cameras.Keys()) {
      const ConfigNode c = cameras[camera];
      c.ExpectKeys({"position_mm", "rotation_rad", "per_row"});
      if (c.GetBool("per_row", false)) noise.per_row_cameras.insert(camera);
      if (c.Has("position_mm")) {
        const auto v = c["position_mm"].AsPositiveDoubles(3);
        noise.position_sigma_mm[camera] = Eigen::Vector3d(v[0], v[1], v[2]);
      }
      if (c.Has("rotation_rad")) {
        const auto v = c["rotation_rad"].AsPositiveDoubles(3);
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
    e.config = config.FlowText();
    e.name = prefix + "." + config["type"].AsString();
    for (int k = 2; std::any_of(problem->effects.begin(), problem->effects.end(),
                                [&](const WorkcellEffect& x) { return x.name == e.name; });
         ++k) {
      e.name = prefix + "." + config["type"].AsString() + "_" + std::to_string(k);
    }
    problem->effects.push_back(e);
  }
}

namespace {

// The job kinds this reader reads; `kinematic` was the delta's own reader before there was one.
void CheckKind(const ConfigNode& kind_node) {
  const std::string kind = kind_node.AsString();
  if (kind == "workcell" || kind == "homing") return;
  if (kind == "kinematic") {
    throw kind_node.Error("'job: kinematic' is now a workcell job",
                          "Write job: workcell with the robot under robots:, its marker under "
                          "tools:, world_target: none, the camera under cameras:, and "
                          "formulation: inverse as residual: joint_space (docs/formats.md)");
  }
  throw kind_node.Error("unknown job kind '" + kind + "'", "Use workcell or homing");
}

CameraModel ReadCameraModel(const ConfigNode& root) {
  const std::string name = root.GetString("camera_model", "static_cameras");
  if (name == "static_cameras") return CameraModel::kStaticCameras;
  if (name == "per_frame") return CameraModel::kPerFrame;
  throw root["camera_model"].Error("unknown camera model '" + name + "'",
                                   "Use static_cameras or per_frame");
}

// `outliers: robust | plain | off` (outliers.h).
OutlierTest ReadOutlierTest(const ConfigNode& root) {
  const std::string name = root.GetString("outliers", "robust");
  if (name == "robust") return OutlierTest::kRobust;
  if (name == "plain") return OutlierTest::kPlain;
  if (name == "off") return OutlierTest::kOff;
  throw root["outliers"].Error("unknown outlier test '" + name + "'",
                               "Use robust (the default), plain or off");
}

// `residual: cartesian | joint_space`; joint space where every robot has inverse kinematics.
ResidualForm ReadResidual(const ConfigNode& root, const WorkcellProblem& problem) {
  const std::string name = root.GetString("residual", "cartesian");
  if (name == "cartesian") return ResidualForm::kCartesian;
  if (name != "joint_space") {
    throw root["residual"].Error("unknown residual '" + name + "'", "Use cartesian or joint_space");
  }
  const ConfigNode node = root["residual"];
  for (const auto& robot : problem.robots) {
    if (!robot.model->has_inverse() || robot.model->num_joints() != 3) {
      throw node.Error("the joint-space residual needs position inverse kinematics, and '" +
                           robot.name + "' has none",
                       "Use residual: cartesian");
    }
  }
  if (problem.camera_model != CameraModel::kStaticCameras || problem.use_tool_rotation ||
      !problem.effects.empty()) {
    throw node.Error(
        "the joint-space residual compares positions seen by static cameras, "
        "without effects",
        "Use residual: cartesian");
  }
  return ResidualForm::kJointSpace;
}

// A target name is one marker in the recording: two robots both listing `tool` would each be
// fitted to the other's observations. Refused at the second one, with where the first is.
void CheckToolNamesUnique(const ConfigNode& tools, const std::string& robot,
                          const std::string& world_target,
                          std::map<std::string, std::string>* carrier) {
  for (const auto& target : tools.Keys()) {
    std::string other;
    if (!world_target.empty() && target == world_target) other = "the world target";
    const auto seen = carrier->find(target);
    if (seen != carrier->end()) other = "robot '" + seen->second + "'";
    if (!other.empty()) {
      throw InputError(tools.KeyLocation(target),
                       "robots." + robot + ".tools: target '" + target + "' is already " +
                           (seen != carrier->end() ? "a tool of " : "") + other,
                       "A target name is one marker in the recording; give each robot's tool "
                       "its own name, as recording.yaml does");
    }
    (*carrier)[target] = robot;
  }
}

// `robots:`, their effects and the cell-wide measurement effects; where each is named.
void ReadRobots(const ConfigNode& root, Registry& registry, WorkcellJob* job) {
  WorkcellProblem& problem = job->problem;
  const ConfigNode robots = root["robots"];
  std::map<std::string, std::string> carrier;  // target -> robot
  for (const auto& name : robots.Keys()) {
    const ConfigNode robot = robots[name];
    // Without a world target the first robot's base is the world; the others stand in it.
    const bool world_is_base = problem.world_target.empty() && problem.robots.empty();
    problem.robots.push_back(ReadRobot(name, robot, world_is_base, registry));
    job->locations["robots." + name] = robot.location();
    if (robot.Has("tools")) {
      CheckToolNamesUnique(robot["tools"], name, problem.world_target, &carrier);
    }
    for (const std::string list : {"tools", "cameras"}) {
      if (!robot.Has(list)) continue;
      for (const auto& key : robot[list].Keys()) {
        const auto entry = robot[list].Optional(key);
        job->locations["robots." + name + "." + list + "." + key] =
            entry ? entry->location() : robot[list].location();
      }
    }
  }
  for (const auto& name : robots.Keys()) {
    if (robots[name].Has("effects")) {
      AddEffects(robots[name]["effects"], name, name, registry, &problem);
    }
  }
  if (!root.Has("effects")) return;
  AddEffects(root["effects"], problem.robots.front().name, "camera", registry, &problem);
  for (const auto& e : problem.effects) {
    if (e.name.rfind("camera.", 0) == 0 && e.effect->stage() != EffectStage::kMeasurement) {
      throw root["effects"].Error("'" + e.name + "' acts on a robot's joints or flange",
                                  "List it under that robot's effects:");
    }
  }
}

// `uncertain_inputs:` (workcell_problem.h, UncertainInputs): effects held at zero with a sigma,
// `- {sigma: 0.005, effect: {type: target_scale, targets: [world, tool]}}`, and the robots' held
// model parameters, `robot_model: {mm: 0.5, rad: 0.001}`.
void ReadUncertainInputs(const ConfigNode& node, Registry& registry, WorkcellProblem* problem) {
  node.ExpectKeys({"effects", "robot_model"});
  auto positive = [](const ConfigNode& value) {
    const double sigma = value.AsDouble();
    if (!(sigma > 0.0)) {
      throw value.Error("an uncertainty must be positive",
                        "Give the input's standard uncertainty (1 sigma) in its unit");
    }
    return sigma;
  };
  if (node.Has("effects")) {
    for (const auto& entry : node["effects"].Elements()) {
      entry.ExpectKeys({"sigma", "effect"});
      const ConfigNode config = entry["effect"];
      const std::string type = config["type"].AsString();
      WorkcellEffect e;
      e.robot = problem->robots.front().name;
      e.effect = registry.CreateEffect(type, config, *problem->robots.front().model);
      e.config = config.FlowText();
      e.name = "uncertain." + type;
      for (int k = 2; std::any_of(problem->uncertain_inputs.effects.begin(),
                                  problem->uncertain_inputs.effects.end(),
                                  [&](const auto& x) { return x.first.name == e.name; });
           ++k) {
        e.name = "uncertain." + type + "_" + std::to_string(k);
      }
      if (e.effect->stage() != EffectStage::kMeasurement) {
        throw config["type"].Error("'" + type + "' acts on a robot's joints or flange",
                                   "Uncertain inputs are measurement effects (a target's size, "
                                   "a camera's focal length); a robot's are under robot_model:");
      }
      problem->uncertain_inputs.effects.push_back({e, positive(entry["sigma"])});
    }
  }
  if (node.Has("robot_model")) {
    const ConfigNode by_unit = node["robot_model"];
    by_unit.ExpectKeys({"mm", "rad"});
    for (const auto& robot : problem->robots) {
      for (const auto& unit : by_unit.Keys()) {
        problem->uncertain_inputs.model_sigma[robot.name][unit] = positive(by_unit[unit]);
      }
    }
  }
}

// Tolerances, cross-validation and gravity.
void ReadOptions(const ConfigNode& root, WorkcellProblem* problem) {
  problem->use_tool_rotation = root.GetBool("use_tool_rotation", false);
  problem->identifiability_tolerance =
      root.GetDoubleIn("identifiability_tolerance", problem->identifiability_tolerance, 1e-16, 0.1,
                       "A relative singular value: 1e-8 is the default");
  problem->weak_vif =
      root.GetDoubleIn("weak_vif", problem->weak_vif, 1.0, 1e300,
                       "A variance inflation factor is at least 1; 1e5 is the default");
  if (root.Has("gravity_base")) {
    const auto g = root["gravity_base"].AsDoubles(3);
    problem->gravity_base = Eigen::Vector3d(g[0], g[1], g[2]);
  }
  if (root.Has("noise")) problem->noise = ReadNoise(root["noise"]);
  if (!root.Has("validation")) {
    problem->leave_one_camera_out = true;
    return;
  }
  const ConfigNode v = root["validation"];
  v.ExpectKeys(
      {"folds", "seed", "compare_camera_models", "leave_one_camera_out", "held_out_setup"});
  problem->folds =
      v.GetIntIn("folds", problem->folds, 0, 1000, "0 turns cross-validation off; 5 is usual");
  if (problem->folds == 1) {
    throw v["folds"].Error("one fold holds nothing out",
                           "0 turns cross-validation off; 5 is usual");
  }
  problem->seed = static_cast<unsigned>(
      v.GetIntIn("seed", 1, 0, 2147483647, "A seed is a whole number, 0 or more"));
  problem->compare_camera_models = v.GetBool("compare_camera_models", false);
  problem->leave_one_camera_out = v.GetBool("leave_one_camera_out", true);
}

// `validation: {held_out_setup: {recording, register_on}}` (held_out_setup.h).
HeldOutSetupSpec ReadHeldOutSetup(const ConfigNode& node, bool recording_must_exist) {
  node.ExpectKeys({"recording", "register_on"});
  HeldOutSetupSpec spec;
  spec.recording = recording_must_exist
                       ? ReadRecordingPath(node["recording"])
                       : node["recording"].ResolvePath(node["recording"].AsString());
  const ConfigNode on = node["register_on"];
  on.ExpectKeys({"first", "every", "poses"});
  const std::string hint =
      "Say which poses register the new setup: {first: N}, {every: K} or {poses: [ids]}";
  if (on.Keys().size() != 1) throw on.Error("register_on takes one of first, every, poses", hint);
  if (on.Has("first")) spec.register_on.first = on.GetIntIn("first", 0, 1, 1000000, hint);
  if (on.Has("every")) spec.register_on.every = on.GetIntIn("every", 0, 2, 1000000, hint);
  if (on.Has("poses")) {
    for (const ConfigNode& pose : on["poses"].Elements()) {
      spec.register_on.poses.push_back(pose.AsInt());
    }
    if (spec.register_on.poses.empty()) throw on["poses"].Error("no pose named", hint);
  }
  return spec;
}

// Where the recording is and where the result goes.
void ReadPaths(const ConfigNode& root, const std::string& path, bool recording_must_exist,
               WorkcellJob* job) {
  job->recording = recording_must_exist
                       ? ReadRecordingPath(root["recording"])
                       : root["recording"].ResolvePath(root["recording"].AsString());
  if (root.Has("validation_recording")) {
    job->validation_recording = ReadRecordingPath(root["validation_recording"]);
  }
  if (root.Has("validation") && root["validation"].Has("held_out_setup")) {
    const ConfigNode node = root["validation"]["held_out_setup"];
    job->held_out_setup = ReadHeldOutSetup(node, recording_must_exist);
    job->held_out_setup_where = node.location();
  }
  const std::string stem = std::filesystem::path(path).stem().string();
  job->output =
      root.Has("output") ? root.ResolvePath(root["output"].AsString()) : "results/" + stem;
}

}  // namespace

WorkcellJob LoadWorkcellJob(const std::string& path, Registry& registry,
                            bool recording_must_exist) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"job",          "description",
                   "recording",    "validation_recording",
                   "output",       "plugin_paths",
                   "world_target", "camera_model",
                   "residual",     "use_tool_rotation",
                   "robots",       "cameras",
                   "noise",        "solver",
                   "validation",   "identifiability_tolerance",
                   "weak_vif",     "effects",
                   "gravity_base", "uncertain_inputs",
                   "diagnosis",    "homing",
                   "outliers"});
  CheckKind(root["job"]);
  WorkcellJob job;
  job.file = path;
  job.kind = root["job"].AsString();
  if (root.Has("plugin_paths")) {
    for (const auto& node : root["plugin_paths"].Elements()) {
      const std::string folder = root.ResolvePath(node.AsString());
      std::error_code unreadable;  // a name the file system refuses is "no folder"
      if (!std::filesystem::is_directory(folder, unreadable)) {
        throw node.Error("no plugin folder at '" + folder + "'",
                         "Point plugin_paths at the folder that holds the plugin libraries");
      }
      registry.LoadFolder(folder);
    }
  }
  ReadPaths(root, path, recording_must_exist, &job);
  WorkcellProblem& problem = job.problem;
  problem.world_target = root.GetString("world_target", problem.world_target);
  if (problem.world_target == "none") problem.world_target.clear();
  job.locations["world_target"] =
      root.Has("world_target") ? root["world_target"].location() : root.location();
  problem.camera_model = ReadCameraModel(root);
  ReadOptions(root, &problem);
  problem.outlier_test = ReadOutlierTest(root);
  if (root.Has("noise") && root["noise"].Has("cameras")) {
    for (const auto& camera : root["noise"]["cameras"].Keys()) {
      job.locations["noise.cameras." + camera] = root["noise"]["cameras"][camera].location();
    }
  }
  ReadRobots(root, registry, &job);
  if (root.Has("uncertain_inputs")) {
    ReadUncertainInputs(root["uncertain_inputs"], registry, &problem);
  }
  if (root.Has("cameras")) {
    problem.cameras = ReadCameras(root["cameras"]);
    for (const auto& camera : root["cameras"].Keys()) {
      job.locations["cameras." + camera] = root["cameras"][camera].location();
    }
  }
  problem.residual = ReadResidual(root, problem);
  if (root.Has("homing")) job.homing = root["homing"];
  if (job.kind == "homing" && !root.Has("solver")) return job;
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

namespace {

// Every camera the job's noise: and cameras: sections name is in the recording; a start or free
// flags for a camera it lacks would otherwise be ignored without a word.
void CheckJobCamerasRecorded(const WorkcellJob& job, const Recording& recording) {
  std::set<std::string> noise_cameras;
  for (const auto& entry : job.problem.noise.position_sigma_mm) noise_cameras.insert(entry.first);
  for (const auto& entry : job.problem.noise.rotation_sigma_rad) noise_cameras.insert(entry.first);
  for (const auto& camera : noise_cameras) {
    if (recording.HasCamera(camera)) continue;
    throw InputError(
        job.Where("noise.cameras." + camera),
        "camera '" + camera + "' under noise: is not in the recording " + recording.folder,
        "Name the cameras as recording.yaml does");
  }
  for (const auto& [camera, settings] : job.problem.cameras) {
    if (recording.HasCamera(camera)) continue;
    throw InputError(
        job.Where("cameras." + camera),
        "camera '" + camera + "' under cameras: is not in the recording " + recording.folder,
        "Name the cameras as recording.yaml does");
  }
}

// A robot of the job is in the recording with as many joints, and carries there what the job
// says it carries: its targets, and its cameras (eye-in-hand).
void CheckRobotRecorded(const WorkcellJob& job, const WorkcellRobot& robot,
                        const Recording& recording) {
  const auto joints = recording.robots.find(robot.name);
  if (joints == recording.robots.end()) {
    throw InputError(job.Where("robots." + robot.name),
                     "robot '" + robot.name + "' is not in the recording " + recording.folder,
                     "Name the robot as recording.yaml does");
  }
  if (joints->second != robot.model->num_joints()) {
    throw InputError(job.Where("robots." + robot.name),
                     "robot '" + robot.name + "' has " + std::to_string(joints->second) +
                         " joints in the recording but " +
                         std::to_string(robot.model->num_joints()) + " in " + robot.model_file,
                     "Use the robot config that matches the recorded robot");
  }
  for (const auto& tool : robot.tools) {
    if (tool.is_camera()) {
      const auto mount = recording.camera_mounts.find(tool.camera);
      if (mount == recording.camera_mounts.end() || mount->second != robot.name) {
        throw InputError(
            job.Where("robots." + robot.name + ".cameras." + tool.camera),
            "camera '" + tool.camera + "' does not ride on robot '" + robot.name +
                "' in the recording",
            "List under 'cameras:' the cameras recording.yaml puts 'on: " + robot.name + "'");
      }
      continue;
    }
    const auto target = recording.targets.find(tool.target);
    if (target == recording.targets.end() || target->second != robot.name) {
      throw InputError(
          job.Where("robots." + robot.name + ".tools." + tool.target),
          "target '" + tool.target + "' is not carried by robot '" + robot.name +
              "' in the recording",
          "List under 'tools:' the targets recording.yaml puts 'on: " + robot.name + "'");
    }
  }
}

}  // namespace

void ValidateJobAgainstRecording(const WorkcellJob& job, const Recording& recording) {
  CheckJobCamerasRecorded(job, recording);
  const auto world = recording.targets.find(job.problem.world_target);
  if (!job.problem.world_target.empty() &&
      (world == recording.targets.end() || world->second != kWorldCarrier)) {
    throw InputError(job.Where("world_target"),
                     "the recording has no world-fixed target '" + job.problem.world_target + "'",
                     "Set 'world_target:' to a target that recording.yaml puts 'on: world'");
  }
  for (const auto& robot : job.problem.robots) CheckRobotRecorded(job, robot, recording);
  // Angles in the other unit (rad declared deg, or the reverse) against the robot's turns, first:
  // joint readings 57 times too small also make the cell look 57 times too small.
  CheckAngleUnits(job, recording);
  // Lengths a thousand times off (m declared, mm held, or the reverse) against the robot's size.
  CheckLengthScale(job, recording);
}

}  // namespace cellmetry
