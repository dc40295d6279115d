// Pairing a recording's observations with a cell's robots and cameras (workcell_data.h).
#include "cellmetry/cell/workcell_data.h"

#include <cstdio>
#include <optional>
#include <set>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/motion_check.h"

namespace cellmetry {
namespace {

// A command outside the robot config's joint limits cannot have been reached, and one the
// nominal model has no pose for (a delta's rod spheres that do not meet) cannot be fitted.
void CheckCommand(const WorkcellRobot& robot, const Sample& sample, const std::string& file) {
  const RobotLimits& limits = robot.model->limits();
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
  std::vector<double> nominal;
  for (const auto& p : robot.model_parameters) nominal.push_back(p.nominal);
  Pose flange;
  if (!robot.model->Forward(sample.q.data(), nominal.data(), &flange)) {
    throw InputError(
        {file, sample.line, 0},
        "the command has no pose: " + robot.model->ForwardFailure(sample.q.data(), nominal.data()),
        "Check the joint values (rad) and the robot config, or remove this sample");
  }
}

// Every carried target of the job: target -> (robot index, tool index).
std::map<std::string, std::pair<int, int>> CarriedTargets(const WorkcellProblem& spec) {
  std::map<std::string, std::pair<int, int>> carried;
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    for (size_t t = 0; t < spec.robots[r].tools.size(); ++t) {
      carried[spec.robots[r].tools[t].target] = {static_cast<int>(r), static_cast<int>(t)};
    }
  }
  return carried;
}

using WorldSeen = std::map<std::pair<int, std::string>, std::vector<const Observation*>>;

// The world target's usable observations, and per (sample, camera) those seen in that capture.
WorldSeen CollectWorld(const WorkcellProblem& spec, const Recording& recording,
                       WorkcellData* data) {
  WorldSeen seen;
  for (size_t i = 0; i < recording.observations.size(); ++i) {
    const Observation& obs = recording.observations[i];
    if (spec.world_target.empty() || obs.target != spec.world_target) continue;
    if (recording.camera_mounts.count(obs.camera)) continue;  // moves: not a static camera's
    if (!obs.rvec) {
      ++data->skipped["world target without rotation"];
      continue;
    }
    data->world_observations.push_back(static_cast<int>(i));
    seen[{obs.sample, obs.camera}].push_back(&obs);
  }
  return seen;
}

// Several captures of the world target in one sample: their mean pose. One capture is its own
// mean (the usual case: exp_a pairs 7,500 tool observations so, and projecting one rotation
// onto the rotations was a third of pairing them).
Pose MeanPose(const std::vector<const Observation*>& captures) {
  if (captures.size() == 1) {
    return Pose{RotationFromRvec(captures.front()->rvec->data()), captures.front()->position_mm};
  }
  std::vector<Eigen::Matrix3d> rotations;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  for (const auto* w : captures) {
    rotations.push_back(RotationFromRvec(w->rvec->data()));
    position += w->position_mm;
  }
  return Pose{MeanRotation(rotations), position / static_cast<double>(captures.size())};
}

// One carried target's observation as a measurement, or the reason it cannot be one.
std::optional<ToolMeasurement> PairTool(const WorkcellProblem& spec, const Recording& recording,
                                        int index, const std::pair<int, int>& carrier,
                                        const WorldSeen& world, std::string* skipped) {
  const Observation& obs = recording.observations[index];
  ToolMeasurement m;
  m.observation = index;
  m.sample_index = recording.SampleIndex(obs.sample);
  m.robot = carrier.first;
  m.tool = carrier.second;
  const Sample& sample = recording.samples[m.sample_index];
  if (sample.robot != spec.robots[m.robot].name) {
    throw InputError({recording.folder + "/observations.csv", obs.line, 0},
                     "target '" + obs.target + "' is carried by robot '" +
                         spec.robots[m.robot].name + "' but sample " + std::to_string(obs.sample) +
                         " is a state of robot '" + sample.robot + "'",
                     "Point the observation at a sample of the robot that carries the target");
  }
  if (spec.use_tool_rotation && !obs.rvec) {
    *skipped = "tool observation without rotation";
    return std::nullopt;
  }
  const auto seen = world.find({obs.sample, obs.camera});
  if (seen != world.end()) {
    m.has_world_pose = true;
    m.T_cam_world = MeanPose(seen->second);
  } else if (spec.camera_model == CameraModel::kPerFrame) {
    *skipped = "no world target in the same capture (per-frame model)";
    return std::nullopt;
  }
  return m;
}

// Every camera riding on a flange the job identifies: camera -> (robot index, tool index).
std::map<std::string, std::pair<int, int>> MountedCameras(const WorkcellProblem& spec) {
  std::map<std::string, std::pair<int, int>> mounted;
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    for (size_t t = 0; t < spec.robots[r].tools.size(); ++t) {
      if (!spec.robots[r].tools[t].is_camera()) continue;
      mounted[spec.robots[r].tools[t].camera] = {static_cast<int>(r), static_cast<int>(t)};
    }
  }
  return mounted;
}

// What eye in hand does not combine with, said before anything is fitted: its residual
// (eye_in_hand_residual.h) is the Cartesian chain without effects, the board it sees defines
// the world, and its camera moves, so no capture has a world pose of its own.
void CheckEyeInHandSetting(const WorkcellProblem& spec, const Recording& recording) {
  std::string refused, hint;
  if (spec.world_target.empty()) {
    refused = "a world target (the board the camera sees defines the world)";
    hint = "Name the board the camera sees as world_target: (its pose then defines the world)";
  } else if (spec.camera_model != CameraModel::kStaticCameras) {
    refused = "camera_model: static_cameras (a moving camera has no per-frame world pose)";
    hint = "Use camera_model: static_cameras";
  } else if (spec.residual != ResidualForm::kCartesian) {
    refused = "residual: cartesian";
    hint = "Use residual: cartesian";
  } else if (!spec.effects.empty() || !spec.uncertain_inputs.effects.empty()) {
    refused = "a cell without effects (its residual is the geometric chain)";
    hint = "Leave effects: and uncertain effects out of a job with a camera on a flange";
  }
  if (refused.empty()) return;
  throw InputError({recording.folder + "/recording.yaml", 0, 0},
                   "a camera riding on a robot (eye in hand) needs " + refused,
                   hint + " (docs/formats.md, \"Eye in hand\")");
}

// An observation by a camera riding on a flange: of the world target, in a capture of the
// robot that carries it, with its rotation; or the reason it cannot be used.
std::optional<ToolMeasurement> PairMounted(const WorkcellProblem& spec, const Recording& recording,
                                           int index, const std::pair<int, int>& carrier,
                                           std::string* skipped) {
  const Observation& obs = recording.observations[index];
  ToolMeasurement m;
  m.observation = index;
  m.sample_index = recording.SampleIndex(obs.sample);
  m.robot = carrier.first;
  m.tool = carrier.second;
  if (obs.target != spec.world_target) {
    *skipped = "a camera riding on a robot sees a target other than the world target";
  } else if (recording.samples[m.sample_index].robot != spec.robots[m.robot].name) {
    *skipped = "a camera riding on a robot in a sample of another robot";
  } else if (!obs.rvec) {
    *skipped = "world target without rotation";
  } else {
    return m;
  }
  return std::nullopt;
}

// An observation by a camera riding on a robot: a measurement, or counted among the skipped.
void AddMounted(const WorkcellProblem& spec, const Recording& recording,
                const std::map<std::string, std::pair<int, int>>& mounted, int index,
                WorkcellData* data) {
  const Observation& obs = recording.observations[index];
  const auto on = mounted.find(obs.camera);
  std::string skipped = "camera '" + obs.camera + "' rides on robot '" +
                        recording.camera_mounts.at(obs.camera) +
                        "', and the job does not list it under that robot's cameras:";
  const auto m = on == mounted.end() ? std::nullopt
                                     : PairMounted(spec, recording, index, on->second, &skipped);
  if (m) {
    data->tools.push_back(*m);
  } else {
    ++data->skipped[skipped];
  }
}

[[noreturn]] void NothingUsable(const Recording& recording, const WorkcellData& data) {
  std::string reasons;
  for (const auto& [reason, count] : data.skipped) {
    reasons += (reasons.empty() ? "" : "; ") + std::to_string(count) + " x " + reason;
  }
  throw InputError({recording.folder + "/observations.csv", 0, 0},
                   "no usable observation of a robot-carried target" +
                       (reasons.empty() ? std::string() : " (" + reasons + ")"),
                   "Check that the job's robots carry the recording's targets and that "
                   "observations name them");
}

}  // namespace

std::vector<SampleFacts> GatherEffectFacts(const WorkcellProblem& spec,
                                           const Recording& recording) {
  std::vector<SampleFacts> all(recording.samples.size());
  for (const auto& robot : spec.robots) {
    std::vector<double> nominal;
    for (const auto& p : robot.model_parameters) nominal.push_back(p.nominal);
    std::vector<SampleFacts> facts =
        GatherSampleFacts(recording, robot.name, *robot.model, nominal);
    for (size_t i = 0; i < facts.size(); ++i) {
      if (recording.samples[i].robot == robot.name) all[i] = std::move(facts[i]);
    }
  }
  return all;
}

WorkcellData PrepareWorkcellData(const WorkcellProblem& spec, const Recording& recording) {
  WorkcellData data;
  const auto carried = CarriedTargets(spec);
  const auto mounted = MountedCameras(spec);
  if (!mounted.empty()) CheckEyeInHandSetting(spec, recording);
  const WorldSeen world = CollectWorld(spec, recording, &data);
  for (size_t i = 0; i < recording.observations.size(); ++i) {
    const Observation& obs = recording.observations[i];
    if (recording.camera_mounts.count(obs.camera)) {
      AddMounted(spec, recording, mounted, static_cast<int>(i), &data);
      continue;
    }
    if (!spec.world_target.empty() && obs.target == spec.world_target) continue;
    const auto carrier = carried.find(obs.target);
    if (carrier == carried.end()) {
      ++data.skipped["target '" + obs.target + "' is not identified by this job"];
      continue;
    }
    std::string skipped;
    const auto m = PairTool(spec, recording, static_cast<int>(i), carrier->second, world, &skipped);
    if (m) {
      data.tools.push_back(*m);
    } else {
      ++data.skipped[skipped];
    }
  }
  if (data.tools.empty()) NothingUsable(recording, data);
  // Each command once; repeated captures of a pose follow each other with the same joints, and
  // a command is checked by the robot and its joints alone.
  std::set<int> checked;
  const Sample* last_checked = nullptr;
  for (const ToolMeasurement& m : data.tools) {
    if (!checked.insert(m.sample_index).second) continue;
    const Sample& sample = recording.samples[m.sample_index];
    if (last_checked && last_checked->robot == sample.robot && last_checked->q == sample.q) {
      continue;
    }
    CheckCommand(spec.robots[m.robot], sample, recording.folder + "/samples.csv");
    last_checked = &sample;
  }
  CheckRobotsMove(spec, recording, data);
  if (!spec.effects.empty()) data.facts = GatherEffectFacts(spec, recording);
  return data;
}

}  // namespace cellmetry
