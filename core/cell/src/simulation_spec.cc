// Reading a simulation spec (workcell_simulation.h, docs/formats.md): robots and their truth,
// cameras, noise, effects, concealed physics, the timeline.
#include <cmath>
#include <cstdio>
#include <map>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/formats/config_fields.h"
#include "robot_config.h"

namespace cellmetry {
namespace {

// `effects:` entries: {effect: {type: ..., <options>}, values: {<parameter>: <value>}}; a
// parameter not given is zero.
std::vector<SimulatedEffect> ReadSimulatedEffects(const ConfigNode& list, const std::string& owner,
                                                  const RobotModel& model, Registry& registry) {
  std::vector<SimulatedEffect> effects;
  for (const auto& entry : list.Elements()) {
    entry.ExpectKeys({"effect", "values"});
    SimulatedEffect e;
    const ConfigNode config = entry["effect"];
    e.effect = registry.CreateEffect(config["type"].AsString(), config, model);
    e.name = owner + "." + config["type"].AsString();
    const auto& params = e.effect->parameters();
    e.values.assign(params.size(), 0.0);
    if (entry.Has("values")) {
      const ConfigNode values = entry["values"];
      for (const auto& name : values.Keys()) {
        const int index = FindParameter(params, name);
        if (index < 0) {
          std::string known;
          for (const auto& p : params) known += (known.empty() ? "" : ", ") + p.name;
          throw values[name].Error("the effect has no parameter '" + name + "'",
                                   "Its parameters are: " + known);
        }
        e.values[index] = values[name].AsDouble();
      }
    }
    effects.push_back(e);
  }
  return effects;
}

// `poses: {from_recording, every} | {random, lower, upper} | {set, count, camera, seed}`.
void ReadPoses(const ConfigNode& poses, std::mt19937& rng, SimulatedRobot* robot,
               WorkcellSimulationSpec* spec) {
  poses.ExpectKeys({"from_recording", "every", "random", "lower", "upper", "set", "count", "camera",
                    "seed", "repeats"});
  if (poses.Has("set")) {
    PoseSetSpec set;
    set.set = ParsePoseSet(poses["set"]);
    set.count = poses.GetInt("count", set.count);
    if (set.count < 1) throw poses["count"].Error("must be at least 1");
    set.camera = poses.GetString("camera", "");
    robot->pose_set = set;
    spec->noise_seed =
        static_cast<unsigned>(poses.GetIntIn("seed", static_cast<int>(spec->seed) + 1, 0,
                                             2147483647, "A seed is a whole number, 0 or more"));
    if (poses.Has("repeats")) spec->repeats = poses["repeats"].AsInt();
    return;
  }
  if (poses.Has("from_recording")) {
    const Recording source = ReadRecording(poses.ResolvePath(poses["from_recording"].AsString()));
    const int every = poses.GetInt("every", 1);
    if (every < 1) throw poses["every"].Error("must be 1 or more", "1 takes every pose");
    int last_pose = -1, index = 0;
    for (const auto& s : source.samples) {
      if (s.pose == last_pose) continue;  // one entry per commanded pose
      last_pose = s.pose;
      if (index++ % every == 0) robot->joint_poses.push_back(s.q);
    }
    return;
  }
  const int count = poses.GetIntIn("random", 0, 1, 1000000, "How many random poses to draw");
  const int n = robot->model->num_joints();
  const auto lower =
      poses.Has("lower") ? poses["lower"].AsDoubles(n) : std::vector<double>(n, -M_PI);
  const auto upper =
      poses.Has("upper") ? poses["upper"].AsDoubles(n) : std::vector<double>(n, M_PI);
  // uniform_real_distribution(a, b) with a > b is undefined: it drew poses outside both.
  for (int j = 0; j < n; ++j) {
    if (lower[j] > upper[j]) {
      throw poses["lower"].Elements()[static_cast<size_t>(j)].Error(
          "joint " + std::to_string(j + 1) + "'s lower limit is above its upper limit",
          "Give lower <= upper for every joint");
    }
  }
  for (int i = 0; i < count; ++i) {
    std::vector<double> q(n);
    for (int j = 0; j < n; ++j)
      q[j] = std::uniform_real_distribution<double>(lower[j], upper[j])(rng);
    robot->joint_poses.push_back(q);
  }
}

// `tools: {<target>: {xyz, rvec, measures: pose | position}}`; no pose: the model's nominal tool.
void ReadTools(const ConfigNode& tools, SimulatedRobot* robot) {
  for (const auto& target : tools.Keys()) {
    Pose pose = robot->model->nominal_tool();
    if (const auto tool = tools.Optional(target)) {
      tool->ExpectKeys({"xyz", "rvec", "measures"});
      if (tool->Has("xyz") || tool->Has("rvec")) pose = ReadPose(*tool);
      const std::string measures = tool->GetString("measures", "pose");
      if (measures == "position") {
        robot->point_targets.insert(target);
      } else if (measures != "pose") {
        throw(*tool)["measures"].Error("unknown measurement '" + measures + "'",
                                       "Use pose (position and rotation) or position (a dot)");
      }
    }
    robot->T_flange_target[target] = pose;
  }
}

// `cameras: {<name>: {xyz, rvec}}`: cameras riding on the flange (eye in hand), at their true
// T_flange_camera; each sees the world target from every pose.
void ReadMountedCameras(const ConfigNode& cameras, const WorkcellSimulationSpec& spec,
                        SimulatedRobot* robot) {
  for (const auto& name : cameras.Keys()) {
    const ConfigNode node = cameras[name];
    node.ExpectKeys({"xyz", "rvec"});
    if (spec.cameras.count(name)) {
      throw InputError(cameras.KeyLocation(name),
                       "camera '" + name + "' is already a camera standing in the world",
                       "Give the camera on the flange its own name");
    }
    robot->T_flange_camera[name] = ReadPose(node);
  }
}

SimulatedRobot ReadRobot(const std::string& name, const ConfigNode& node, Registry& registry,
                         std::mt19937& rng, WorkcellSimulationSpec* spec) {
  node.ExpectKeys({"model", "base", "tools", "cameras", "model_errors", "errors", "poses",
                   "payloads_kg", "effects"});
  SimulatedRobot robot;
  robot.name = name;
  robot.model = ReadRobotConfig(node, registry).model;
  for (const auto& p : robot.model->parameters()) robot.nominal_values.push_back(p.nominal);
  robot.model_values = robot.nominal_values;
  if (node.Has("model_errors")) {
    const ConfigNode errors = node["model_errors"];
    for (const auto& param : errors.Keys()) {
      const int index = FindParameter(robot.model->parameters(), param);
      if (index < 0) throw errors[param].Error("no model parameter '" + param + "'");
      robot.model_values[index] += errors[param].AsDouble();
    }
  }
  robot.given_values = robot.model_values;
  if (node.Has("errors")) {
    const ConfigNode e = node["errors"];
    e.ExpectKeys({"dimensions_mm", "homing_increments"});
    robot.errors.dimensions_mm = e.GetDouble("dimensions_mm", 0.0);
    robot.errors.homing_increments = e.GetDouble("homing_increments", 0.0);
  }
  if (node.Has("base")) robot.T_world_base = ReadPose(node["base"]);
  if (!node.Has("cameras") || node.Has("tools")) ReadTools(node["tools"], &robot);
  if (node.Has("cameras")) ReadMountedCameras(node["cameras"], *spec, &robot);
  ReadPoses(node["poses"], rng, &robot, spec);
  if (node.Has("payloads_kg")) {
    robot.payloads_kg = node["payloads_kg"].AsDoubles();
    for (double m : robot.payloads_kg) {
      if (!(m >= 0)) throw node["payloads_kg"].Error("a payload is a mass, 0 kg or more");
    }
  }
  if (node.Has("effects")) {
    robot.effects = ReadSimulatedEffects(node["effects"], name, *robot.model, registry);
  }
  return robot;
}

// A camera that records only what it sees must see the world target (at the world's origin)
// from its nominal pose: without it a static camera cannot be placed in the world.
void CheckWorldTargetInView(const ConfigNode& node, const SimulatedCamera& camera) {
  const Eigen::Vector3d p = camera.T_world_cam_nominal.inverse().t;  // the origin, camera axes
  if (InFieldOfView(camera.half_fov_rad, p)) return;
  const double off_x = std::atan2(std::abs(p.x()), p.z());
  const double off_y = std::atan2(std::abs(p.y()), p.z());
  char what[200];
  std::snprintf(what, sizeof what,
                "the world target is outside this camera's field of view (%.0f and %.0f deg off "
                "its axis, %.0f and %.0f deg allowed%s)",
                off_x * 180 / M_PI, off_y * 180 / M_PI, camera.half_fov_rad.x() * 180 / M_PI,
                camera.half_fov_rad.y() * 180 / M_PI, p.z() > 0 ? "" : ", and behind it");
  throw node.Error(what,
                   "Aim the camera at the world's origin, widen half_fov_rad, or leave "
                   "in_view_only out");
}

// `cameras: {<name>: {xyz, rvec, errors: {mm, rad}, half_fov_rad, in_view_only}}` (nominal
// poses).
void ReadCameras(const ConfigNode& cameras, WorkcellSimulationSpec* spec) {
  for (const auto& name : cameras.Keys()) {
    const ConfigNode node = cameras[name];
    node.ExpectKeys({"xyz", "rvec", "errors", "half_fov_rad", "in_view_only"});
    SimulatedCamera camera;
    camera.T_world_cam_nominal = ReadPose(node);
    if (node.Has("errors")) {
      const ConfigNode e = node["errors"];
      e.ExpectKeys({"mm", "rad"});
      camera.errors.mm = e.GetDouble("mm", 0.0);
      camera.errors.rad = e.GetDouble("rad", 0.0);
    }
    if (node.Has("half_fov_rad")) {
      const auto v = node["half_fov_rad"].AsDoubles(2);
      for (size_t i = 0; i < 2; ++i) {
        if (!(v[i] > 0.0 && v[i] < M_PI / 2)) {
          throw node["half_fov_rad"].Elements()[i].Error(
              "a half angle of a field of view is between 0 and pi/2 rad",
              "Give half the image's width and height as angles, e.g. [0.759, 0.506] for "
              "87 x 58 deg");
        }
      }
      camera.half_fov_rad = Eigen::Vector2d(v[0], v[1]);
    }
    camera.in_view_only = node.GetBool("in_view_only", false);
    if (camera.in_view_only && !spec->world_target.empty()) CheckWorldTargetInView(node, camera);
    spec->cameras[name] = camera;
    spec->T_world_cam[name] = camera.T_world_cam_nominal;
  }
}

// A standard deviation is 0 (a noise-free simulation) or more; a negative one was taken as
// its absolute value without a word.
Eigen::Vector3d ReadSigma(const ConfigNode& node) {
  const auto v = node.AsDoubles(3);
  for (size_t i = 0; i < 3; ++i) {
    if (v[i] < 0) {
      throw node.Elements()[i].Error("a standard deviation cannot be negative",
                                     "Give the noise's scatter, 0 or more");
    }
  }
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

void ReadNoise(const ConfigNode& noise, WorkcellSimulationSpec* spec) {
  noise.ExpectKeys({"position_mm", "rotation_rad"});
  if (noise.Has("position_mm")) spec->sigma_position_mm = ReadSigma(noise["position_mm"]);
  if (noise.Has("rotation_rad")) spec->sigma_rotation_rad = ReadSigma(noise["rotation_rad"]);
}

void ReadTimeline(const ConfigNode& t, SimulatedTimeline* timeline) {
  t.ExpectKeys({"seconds_per_sample", "temperature_start_c", "temperature_end_c"});
  timeline->seconds_per_sample =
      t.GetDoubleIn("seconds_per_sample", 0.0, 0.0, 1e7, "The time between captures, 0 s or more");
  if (t.Has("temperature_start_c"))
    timeline->temperature_start_c = t["temperature_start_c"].AsDouble();
  if (t.Has("temperature_end_c")) timeline->temperature_end_c = t["temperature_end_c"].AsDouble();
}

// A target name is one physical marker: two robots' tools (or a tool and the world target) of
// the same name would be written to the recording as one target, its observations mixed.
void CheckTargetNamesUnique(const ConfigNode& tools, const std::string& robot,
                            const std::string& world_target,
                            const std::map<std::string, SimulatedCamera>& cameras,
                            std::map<std::string, std::string>* carrier) {
  for (const auto& target : tools.Keys()) {
    std::string other;
    if (target == world_target) other = "the world target";
    if (cameras.count(target)) other = "the name of a camera";
    const auto seen = carrier->find(target);
    if (seen != carrier->end()) other = "a tool of robot '" + seen->second + "'";
    if (!other.empty()) {
      throw InputError(tools.KeyLocation(target),
                       "robots." + robot + ".tools: target '" + target + "' is already " + other,
                       "Give every robot's tool its own name (e.g. '" + robot + "_" + target +
                           "'): a target name is one marker in the recording");
    }
    (*carrier)[target] = robot;
  }
}

// Whether some robot carries cameras on its flange (eye in hand): the spec then needs no
// static `cameras:`.
bool CamerasRideOnRobots(const ConfigNode& root) {
  if (!root.Has("robots") || !root["robots"].IsMap()) return false;
  for (const auto& name : root["robots"].Keys()) {
    if (root["robots"][name].Has("cameras")) return true;
  }
  return false;
}

}  // namespace

WorkcellSimulationSpec LoadWorkcellSimulation(const std::string& path, Registry& registry,
                                              const DisturbanceReader& read_disturbance) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"simulation", "description", "seed", "robots", "cameras", "world_target",
                   "noise", "repeats", "images", "effects", "timeline", "concealed",
                   "gravity_base"});
  if (root["simulation"].AsString() != "workcell") {
    throw root["simulation"].Error(
        "unknown simulation kind '" + root["simulation"].AsString() + "'",
        "Use simulation: workcell (a delta arm is a cell too: "
        "docs/formats.md)");
  }
  WorkcellSimulationSpec spec;
  spec.seed = static_cast<unsigned>(
      root.GetIntIn("seed", 1, 0, 2147483647, "A seed is a whole number, 0 or more"));
  spec.noise_seed = spec.seed;
  spec.repeats = root.GetIntIn("repeats", 1, 1, 1000, "Captures per commanded pose");
  if (root.Has("gravity_base")) {  // m/s^2 in every base frame (a robot on a wall: not -z)
    const auto g = root["gravity_base"].AsDoubles(3);
    spec.gravity_base = Eigen::Vector3d(g[0], g[1], g[2]);
  }
  spec.world_target = root.GetString("world_target", spec.world_target);
  if (spec.world_target == "none") spec.world_target.clear();
  if (root.Has("images")) spec.images = root["images"];
  if (root.Has("cameras") || !CamerasRideOnRobots(root)) ReadCameras(root["cameras"], &spec);
  std::mt19937 rng(spec.seed + 7919);
  const ConfigNode robots = root["robots"];
  std::map<std::string, std::string> carrier;  // target -> robot (or "world", a camera)
  for (const auto& name : robots.Keys()) {
    spec.robots.push_back(ReadRobot(name, robots[name], registry, rng, &spec));
    if (robots[name].Has("tools")) {
      CheckTargetNamesUnique(robots[name]["tools"], name, spec.world_target, spec.cameras,
                             &carrier);
    }
  }
  if (spec.repeats < 1) throw root["repeats"].Error("must be at least 1");
  std::mt19937 truth_rng(spec.seed);
  DrawTruth(&spec, truth_rng);
  if (root.Has("effects")) {
    if (spec.robots.empty()) throw root["effects"].Error("effects need a robot");
    spec.measurement_effects =
        ReadSimulatedEffects(root["effects"], "camera", *spec.robots.front().model, registry);
    for (const auto& e : spec.measurement_effects) {
      if (e.effect->stage() != EffectStage::kMeasurement) {
        throw root["effects"].Error("'" + e.name + "' acts on a robot's joints or flange",
                                    "List it under that robot's effects:");
      }
    }
  }
  if (root.Has("concealed")) {
    if (!read_disturbance) {
      throw root["concealed"].Error("this program reads no concealed physics",
                                    "Simulate with `cellmetry simulate`, which reads them");
    }
    for (const auto& node : root["concealed"].Elements()) {
      spec.concealed.push_back(read_disturbance(node));
    }
  }
  if (root.Has("timeline")) ReadTimeline(root["timeline"], &spec.timeline);
  if (root.Has("noise")) ReadNoise(root["noise"], &spec);
  return spec;
}

}  // namespace cellmetry
