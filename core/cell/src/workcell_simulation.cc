#include "cellmetry/cell/workcell_simulation.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "cellmetry/model/effect_context.h"
#include "cellmetry/basics/error.h"
#include "cellmetry/cell/job.h"
#include "effect_residuals.h"

namespace cellmetry {
namespace {

// exp(n) R with n ~ N(0, sigma) about the camera axes; position + N(0, sigma) along them.
Observation Measure(int sample, const std::string& camera, const std::string& target,
                    const Pose& T_cam_target, const WorkcellSimulationSpec& spec,
                    std::mt19937& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  Observation obs;
  obs.sample = sample;
  obs.camera = camera;
  obs.target = target;
  Eigen::Vector3d dp, dr;
  for (int i = 0; i < 3; ++i) {
    dp[i] = unit(rng) * spec.sigma_position_mm[i];
    dr[i] = unit(rng) * spec.sigma_rotation_rad[i];
  }
  obs.position_mm = T_cam_target.t + dp;
  obs.rvec = RvecFromRotation(RotationFromRvec(dr.data()) * T_cam_target.R);
  return obs;
}


// Samples in capture order: every robot's commanded poses, `repeats` captures each, on the
// timeline. Poses the model cannot reach are left out.
std::vector<Sample> PlanSamples(const WorkcellSimulationSpec& spec) {
  std::vector<Sample> samples;
  int pose_id = 0;
  for (const auto& robot : spec.robots) {
    for (size_t k = 0; k < robot.joint_poses.size(); ++k) {
      const std::vector<double>& q = robot.joint_poses[k];
      Pose T_base_flange;
      if (!robot.model->Forward(q.data(), robot.model_values.data(), &T_base_flange)) continue;
      for (int repeat = 0; repeat < spec.repeats; ++repeat) {
        Sample sample;
        sample.id = static_cast<int>(samples.size());
        sample.robot = robot.name;
        sample.pose = pose_id;
        sample.q = q;
        if (!robot.payloads_kg.empty()) {
          sample.payload_kg = robot.payloads_kg[k % robot.payloads_kg.size()];
        }
        samples.push_back(sample);
      }
      ++pose_id;
    }
  }
  const SimulatedTimeline& clock = spec.timeline;
  for (size_t i = 0; i < samples.size(); ++i) {
    if (clock.seconds_per_sample > 0) samples[i].time_s = clock.seconds_per_sample * i;
    if (clock.temperature_start_c && clock.temperature_end_c) {
      const double f = samples.size() > 1 ? double(i) / (samples.size() - 1) : 0.0;
      samples[i].temperature_c = *clock.temperature_start_c +
                                 f * (*clock.temperature_end_c - *clock.temperature_start_c);
    }
  }
  return samples;
}

// The effects of a robot's chain (its own and the measurement effects) and their values.
void ChainEffects(const WorkcellSimulationSpec& spec, const SimulatedRobot& robot,
                  std::vector<const Effect*>* effects, std::vector<const double*>* values) {
  for (const auto* list : {&robot.effects, &spec.measurement_effects}) {
    for (const auto& e : *list) {
      effects->push_back(e.effect.get());
      values->push_back(e.values.data());
    }
  }
}

}  // namespace

Recording SimulateWorkcell(const WorkcellSimulationSpec& spec, WorkcellTruth* truth) {
  std::mt19937 rng(spec.seed);
  Recording recording;
  recording.description = "simulated workcell (cellmetry simulate, seed " +
                          std::to_string(spec.seed) + ")";
  for (const auto& [camera, pose] : spec.T_world_cam) recording.cameras.push_back(camera);
  recording.targets[spec.world_target] = kWorldCarrier;
  for (const auto& robot : spec.robots) {
    recording.robots[robot.name] = robot.model->num_joints();
    for (const auto& [target, pose] : robot.T_flange_target) recording.targets[target] = robot.name;
  }
  recording.samples = PlanSamples(spec);
  for (const auto& robot : spec.robots) {
    const std::vector<SampleFacts> facts =
        GatherSampleFacts(recording, robot.name, *robot.model, robot.model_values);
    std::vector<const Effect*> effects;
    std::vector<const double*> values;
    ChainEffects(spec, robot, &effects, &values);
    std::vector<std::pair<const Disturbance*, std::vector<DisturbanceAction>>> hidden;
    for (const auto& c : spec.concealed) {
      if (c->ActsOn(robot.name)) {
        hidden.push_back({c.get(), c->Actions(recording, facts, spec.gravity_base)});
      }
    }
    for (size_t i = 0; i < recording.samples.size(); ++i) {
      const Sample& sample = recording.samples[i];
      if (sample.robot != robot.name) continue;
      std::vector<double> params = robot.model_values;
      double flange_scale = 0.0;
      for (const auto& [physics, actions] : hidden) {
        for (size_t j = 0; j < actions[i].dq.size(); ++j) {
          const int offset = robot.model->JointOffsetParameter(static_cast<int>(j));
          if (offset >= 0) params[offset] += actions[i].dq[j];
        }
        flange_scale += actions[i].flange_scale;
      }
      Pose T_base_flange;
      EffectContext context = ContextOf(facts[i], spec.gravity_base);
      if (!FlangeWithEffects(*robot.model, params.data(), effects, values.data(), context,
                             &T_base_flange)) {
        throw InputError({"", 0, 0}, "the concealed effects move sample " +
                                         std::to_string(sample.id) + " out of the robot's reach",
                         "Use smaller effect values");
      }
      T_base_flange.t *= 1.0 + flange_scale;
      for (const auto& [camera, T_world_cam] : spec.T_world_cam) {
        context.camera = camera;
        auto measure = [&](const std::string& target, Pose T_cam_target) {
          context.target = target;
          ApplyMeasurement(effects, values.data(), context, &T_cam_target);
          for (const auto& [physics, actions] : hidden) {
            const auto& shift = actions[i].camera_shift_mm;
            if (shift && physics->camera_name() == camera) T_cam_target.t += *shift;
          }
          recording.observations.push_back(Measure(sample.id, camera, target, T_cam_target, spec, rng));
        };
        const Pose T_cam_world = T_world_cam.inverse();
        measure(spec.world_target, T_cam_world);
        for (const auto& [target, T_flange_target] : robot.T_flange_target) {
          measure(target, T_cam_world * robot.T_world_base * T_base_flange * T_flange_target);
        }
      }
    }
  }
  if (truth) {
    for (const auto& robot : spec.robots) {
      truth->frames[robot.name + ".base"] = {"world", robot.T_world_base};
      for (const auto& [target, pose] : robot.T_flange_target) {
        truth->frames[target] = {robot.name + ".flange", pose};
      }
      const auto& params = robot.model->parameters();
      for (size_t i = 0; i < params.size(); ++i) {
        truth->model[robot.name + ".model." + params[i].name] = robot.model_values[i];
      }
    }
    for (const auto& robot : spec.robots) {
      for (const auto* list : {&robot.effects, &spec.measurement_effects}) {
        for (const auto& e : *list) {
          const auto& params = e.effect->parameters();
          for (size_t i = 0; i < params.size(); ++i) {
            truth->model[e.name + "." + params[i].name] = e.values[i];
          }
        }
      }
    }
    for (const auto& [camera, pose] : spec.T_world_cam) truth->frames[camera] = {"world", pose};
    for (const auto& c : spec.concealed) truth->model["concealed." + c->name() + ".magnitude"] = c->size();
  }
  return recording;
}

std::vector<SampleView> WorkcellViews(const WorkcellSimulationSpec& spec,
                                      const Recording& recording) {
  std::vector<SampleView> views;
  for (const auto& sample : recording.samples) {
    const auto robot = std::find_if(spec.robots.begin(), spec.robots.end(),
                                    [&](const SimulatedRobot& r) { return r.name == sample.robot; });
    Pose T_base_flange;
    if (robot == spec.robots.end() ||
        !robot->model->Forward(sample.q.data(), robot->model_values.data(), &T_base_flange)) {
      continue;
    }
    for (const auto& [camera, T_world_cam] : spec.T_world_cam) {
      SampleView view{sample.id, camera, {}};
      const Pose T_cam_world = T_world_cam.inverse();
      view.T_cam_target[spec.world_target] = T_cam_world;
      for (const auto& [target, T_flange_target] : robot->T_flange_target) {
        view.T_cam_target[target] = T_cam_world * robot->T_world_base * T_base_flange * T_flange_target;
      }
      views.push_back(view);
    }
  }
  return views;
}

std::vector<std::string> CameraNames(const WorkcellSimulationSpec& spec) {
  std::vector<std::string> names;
  for (const auto& [camera, pose] : spec.T_world_cam) names.push_back(camera);
  return names;
}

std::vector<std::string> TargetNames(const WorkcellSimulationSpec& spec) {
  std::vector<std::string> names{spec.world_target};
  for (const auto& robot : spec.robots) {
    for (const auto& [target, pose] : robot.T_flange_target) names.push_back(target);
  }
  return names;
}

std::string TruthYaml(const WorkcellTruth& truth) {
  YAML::Emitter out;
  out << YAML::Comment("simulation truth: never read by a calibration; lengths mm, angles rad");
  out << YAML::BeginMap << YAML::Key << "format" << YAML::Value << "cellmetry-truth/1";
  out << YAML::Key << "frames" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, frame] : truth.frames) {
    const Eigen::Vector3d rvec = RvecFromRotation(frame.pose.R);
    out << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "parent" << YAML::Value << frame.parent;
    out << YAML::Key << "xyz" << YAML::Value
        << std::vector<double>{frame.pose.t.x(), frame.pose.t.y(), frame.pose.t.z()};
    out << YAML::Key << "rvec" << YAML::Value << std::vector<double>{rvec.x(), rvec.y(), rvec.z()};
    out << YAML::EndMap;
  }
  out << YAML::EndMap << YAML::Key << "model" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, value] : truth.model) out << YAML::Key << name << YAML::Value << value;
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

WorkcellTruth ReadTruth(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"format", "frames", "model"});
  if (root["format"].AsString() != "cellmetry-truth/1") {
    throw root["format"].Error("unsupported truth format", "Expected cellmetry-truth/1");
  }
  WorkcellTruth truth;
  const ConfigNode frames = root["frames"];
  for (const auto& name : frames.Keys()) {
    const ConfigNode frame = frames[name];
    frame.ExpectKeys({"parent", "xyz", "rvec"});
    truth.frames[name] = {frame["parent"].AsString(), ReadPose(frame)};
  }
  if (root.Has("model")) {
    const ConfigNode model = root["model"];
    for (const auto& name : model.Keys()) truth.model[name] = model[name].AsDouble();
  }
  return truth;
}

WorkcellEvaluation EvaluateWorkcell(const nlohmann::json& result, const WorkcellTruth& truth,
                                    const std::string& truth_origin) {
  WorkcellEvaluation evaluation;
  auto vec = [](const nlohmann::json& j) {
    return Eigen::Vector3d(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  };
  static const char* kAxes[3] = {"x", "y", "z"};
  for (const auto& [name, frame] : result.at("frames").items()) {
    const auto it = truth.frames.find(name);
    if (it == truth.frames.end()) {
      throw InputError({truth_origin, 0, 0}, "the truth has no frame '" + name + "'",
                       "Evaluate a result against the truth of the same simulation");
    }
    const Eigen::Vector3d t = vec(frame.at("xyz_mm")), rvec = vec(frame.at("rvec_rad"));
    const Eigen::Vector3d dt = t - it->second.pose.t;
    const Eigen::Vector3d dr = RotationError<double>(RotationFromRvec(rvec.data()),
                                                     it->second.pose.R);
    const Eigen::Vector3d st = vec(frame.at("sigma_xyz_mm")), sr = vec(frame.at("sigma_rot_rad"));
    for (int i = 0; i < 3; ++i) {
      if (st[i] > 0) {
        evaluation.quantities.push_back({name + "." + kAxes[i], "mm", dt[i], st[i]});
        evaluation.max_translation_error_mm =
            std::max(evaluation.max_translation_error_mm, std::abs(dt[i]));
      }
      if (sr[i] > 0) {
        evaluation.quantities.push_back({name + ".rot_" + kAxes[i], "rad", dr[i], sr[i]});
        evaluation.max_rotation_error_rad =
            std::max(evaluation.max_rotation_error_rad, std::abs(dr[i]));
      }
    }
  }
  for (const auto& p : result.at("model_parameters")) {
    if (p.at("held").get<bool>()) continue;
    const std::string name = p.at("name");
    const auto it = truth.model.find(name);
    // A block the simulation has no truth for at all (a nuisance effect the job added, such as
    // a detection bias) is not scored; a missing entry of a simulated block is an error.
    const std::string block = name.substr(0, name.find('.', name.find('.') + 1) + 1);
    const bool block_simulated = std::any_of(truth.model.begin(), truth.model.end(), [&](const auto& t) {
      return t.first.rfind(block, 0) == 0;
    });
    if (it == truth.model.end() && !block_simulated) continue;
    if (it == truth.model.end()) {
      throw InputError({truth_origin, 0, 0}, "the truth has no model parameter '" + name + "'",
                       "Evaluate a result against the truth of the same simulation");
    }
    const std::string unit = p.at("unit");
    const double error = p.at("value").get<double>() - it->second;
    evaluation.quantities.push_back({name, unit, error, p.at("sigma").get<double>()});
    double& worst = unit == "rad" ? evaluation.max_rotation_error_rad
                                  : evaluation.max_translation_error_mm;
    worst = std::max(worst, std::abs(error));
  }
  for (const auto& q : evaluation.quantities) {
    evaluation.max_abs_normalized = std::max(evaluation.max_abs_normalized, std::abs(q.normalized()));
  }
  return evaluation;
}

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

WorkcellSimulationSpec LoadWorkcellSimulation(const std::string& path, Registry& registry,
                                              const DisturbanceReader& read_disturbance) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"simulation", "description", "seed", "robots", "cameras", "world_target",
                   "noise", "repeats", "images", "effects", "timeline", "concealed"});
  if (root["simulation"].AsString() != "workcell") {
    throw root["simulation"].Error("unknown simulation kind", "This version simulates: workcell");
  }
  WorkcellSimulationSpec spec;
  spec.seed = static_cast<unsigned>(root.GetInt("seed", 1));
  spec.repeats = root.GetInt("repeats", 1);
  spec.world_target = root.GetString("world_target", spec.world_target);
  if (root.Has("images")) spec.images = root["images"];
  std::mt19937 rng(spec.seed + 7919);
  const ConfigNode robots = root["robots"];
  for (const auto& name : robots.Keys()) {
    const ConfigNode node = robots[name];
    node.ExpectKeys({"model", "base", "tools", "model_errors", "poses", "payloads_kg", "effects"});
    SimulatedRobot robot;
    robot.name = name;
    const ConfigNode config = ConfigNode::LoadFile(node.ResolvePath(node["model"].AsString()));
    robot.model = registry.CreateRobotModel(config["type"].AsString(), config);
    for (const auto& p : robot.model->parameters()) robot.model_values.push_back(p.nominal);
    if (node.Has("model_errors")) {
      const ConfigNode errors = node["model_errors"];
      for (const auto& param : errors.Keys()) {
        const int index = FindParameter(robot.model->parameters(), param);
        if (index < 0) throw errors[param].Error("no model parameter '" + param + "'");
        robot.model_values[index] += errors[param].AsDouble();
      }
    }
    robot.T_world_base = ReadPose(node["base"]);
    const ConfigNode tools = node["tools"];
    for (const auto& target : tools.Keys()) robot.T_flange_target[target] = ReadPose(tools[target]);
    const ConfigNode poses = node["poses"];
    poses.ExpectKeys({"from_recording", "every", "random", "lower", "upper"});
    if (poses.Has("from_recording")) {
      const Recording source = ReadRecording(poses.ResolvePath(poses["from_recording"].AsString()));
      const int every = poses.GetInt("every", 1);
      if (every < 1) throw poses["every"].Error("must be 1 or more", "1 takes every pose");
      int last_pose = -1, index = 0;
      for (const auto& s : source.samples) {
        if (s.pose == last_pose) continue;  // one entry per commanded pose
        last_pose = s.pose;
        if (index++ % every == 0) robot.joint_poses.push_back(s.q);
      }
    } else {
      const int count = poses["random"].AsInt();
      const int n = robot.model->num_joints();
      const auto lower = poses.Has("lower") ? poses["lower"].AsDoubles(n)
                                            : std::vector<double>(n, -M_PI);
      const auto upper = poses.Has("upper") ? poses["upper"].AsDoubles(n)
                                            : std::vector<double>(n, M_PI);
      for (int i = 0; i < count; ++i) {
        std::vector<double> q(n);
        for (int j = 0; j < n; ++j) q[j] = std::uniform_real_distribution<double>(lower[j], upper[j])(rng);
        robot.joint_poses.push_back(q);
      }
    }
    if (node.Has("payloads_kg")) {
      robot.payloads_kg = node["payloads_kg"].AsDoubles();
      for (double m : robot.payloads_kg) {
        if (!(m >= 0)) throw node["payloads_kg"].Error("a payload is a mass, 0 kg or more");
      }
    }
    if (node.Has("effects")) {
      robot.effects = ReadSimulatedEffects(node["effects"], name, *robot.model, registry);
    }
    spec.robots.push_back(robot);
  }
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
  if (root.Has("timeline")) {
    const ConfigNode t = root["timeline"];
    t.ExpectKeys({"seconds_per_sample", "temperature_start_c", "temperature_end_c"});
    spec.timeline.seconds_per_sample = t.GetDouble("seconds_per_sample", 0.0);
    if (t.Has("temperature_start_c")) spec.timeline.temperature_start_c = t["temperature_start_c"].AsDouble();
    if (t.Has("temperature_end_c")) spec.timeline.temperature_end_c = t["temperature_end_c"].AsDouble();
  }
  const ConfigNode cameras = root["cameras"];
  for (const auto& camera : cameras.Keys()) spec.T_world_cam[camera] = ReadPose(cameras[camera]);
  if (root.Has("noise")) {
    const ConfigNode noise = root["noise"];
    noise.ExpectKeys({"position_mm", "rotation_rad"});
    if (noise.Has("position_mm")) {
      const auto v = noise["position_mm"].AsDoubles(3);
      spec.sigma_position_mm = Eigen::Vector3d(v[0], v[1], v[2]);
    }
    if (noise.Has("rotation_rad")) {
      const auto v = noise["rotation_rad"].AsDoubles(3);
      spec.sigma_rotation_rad = Eigen::Vector3d(v[0], v[1], v[2]);
    }
  }
  return spec;
}

}  // namespace cellmetry
