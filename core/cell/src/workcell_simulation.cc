// The one simulator (workcell_simulation.h): samples, effects, concealed physics, noise.
#include "cellmetry/cell/workcell_simulation.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "cellmetry/basics/error.h"
#include "cellmetry/model/effect_chain.h"
#include "cellmetry/model/effect_context.h"
#include "workcell_residuals.h"

namespace cellmetry {
namespace {

// The random stream of a simulation's measurements: one normal distribution across them, so
// that a position-only measurement (three draws) leaves no pair half used out of the stream.
struct Noise {
  std::mt19937& rng;
  std::normal_distribution<double> unit{0.0, 1.0};
};

// exp(n) R with n ~ N(0, sigma) about the camera axes; position + N(0, sigma) along them. A point
// target (`position_only`) has no rotation to measure.
Observation Measure(int sample, const std::string& camera, const std::string& target,
                    const Pose& T_cam_target, const WorkcellSimulationSpec& spec,
                    bool position_only, Noise& noise) {
  Observation obs;
  obs.sample = sample;
  obs.camera = camera;
  obs.target = target;
  Eigen::Vector3d dp, dr;
  for (int i = 0; i < 3; ++i) {
    dp[i] = noise.unit(noise.rng) * spec.sigma_position_mm[i];
    if (!position_only) dr[i] = noise.unit(noise.rng) * spec.sigma_rotation_rad[i];
  }
  obs.position_mm = T_cam_target.t + dp;
  if (!position_only) obs.rvec = RvecFromRotation(RotationFromRvec(dr.data()) * T_cam_target.R);
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
      samples[i].temperature_c =
          *clock.temperature_start_c + f * (*clock.temperature_end_c - *clock.temperature_start_c);
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

// The commands of every robot's pose set, drawn from `rng` (before any noise).
WorkcellSimulationSpec WithPoseSets(const WorkcellSimulationSpec& spec, std::mt19937& rng) {
  WorkcellSimulationSpec out = spec;
  for (auto& robot : out.robots) {
    if (!robot.pose_set) continue;
    const PoseSetGeometry g = PoseSetGeometryOf(out, robot, robot.pose_set->camera);
    robot.joint_poses = DrawPoseSet(g, robot.pose_set->set, robot.pose_set->count, rng);
  }
  return out;
}

// Whether a camera that records only what it sees has the target's origin in its field of view
// (SimulatedCamera::in_view_only); an ideal camera sees everything.
bool Sees(const SimulatedCamera& camera, const Pose& T_cam_target) {
  return !camera.in_view_only || InFieldOfView(camera.half_fov_rad, T_cam_target.t);
}

// One robot's samples measured by every camera that sees them, with its effects and concealed
// physics.
void MeasureRobot(const WorkcellSimulationSpec& spec, const SimulatedRobot& robot,
                  Recording* recording, Noise& noise) {
  const std::vector<SampleFacts> facts =
      GatherSampleFacts(*recording, robot.name, *robot.model, robot.model_values);
  std::vector<const Effect*> effects;
  std::vector<const double*> values;
  ChainEffects(spec, robot, &effects, &values);
  std::vector<std::pair<const Disturbance*, std::vector<DisturbanceAction>>> hidden;
  for (const auto& c : spec.concealed) {
    if (c->ActsOn(robot.name)) {
      hidden.push_back({c.get(), c->Actions(*recording, facts, spec.gravity_base)});
    }
  }
  for (size_t i = 0; i < recording->samples.size(); ++i) {
    const Sample& sample = recording->samples[i];
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
      throw InputError({"", 0, 0},
                       "the concealed effects move sample " + std::to_string(sample.id) +
                           " out of the robot's reach",
                       "Use smaller effect values");
    }
    T_base_flange.t *= 1.0 + flange_scale;
    for (const auto& [camera_name, T_world_cam] : spec.T_world_cam) {
      const std::string& camera =
          camera_name;  // C++17: a lambda cannot capture a structured binding
      context.camera = camera;
      auto measure = [&](const std::string& target, Pose T_cam_target) {
        context.target = target;
        ApplyMeasurement(effects, values.data(), context, &T_cam_target);
        for (const auto& physics : spec.concealed) physics->MeasureInCamera(camera, &T_cam_target);
        for (const auto& [physics, actions] : hidden) {
          const auto& shift = actions[i].camera_shift_mm;
          if (shift && physics->camera_name() == camera) T_cam_target.t += *shift;
        }
        recording->observations.push_back(Measure(sample.id, camera, target, T_cam_target, spec,
                                                  robot.point_targets.count(target) > 0, noise));
      };
      const Pose T_cam_world = T_world_cam.inverse();
      if (!spec.world_target.empty()) measure(spec.world_target, T_cam_world);
      const auto seen = spec.cameras.find(camera);
      for (const auto& [target, T_flange_target] : robot.T_flange_target) {
        const Pose T_cam_target =
            T_cam_world * robot.T_world_base * T_base_flange * T_flange_target;
        if (seen == spec.cameras.end() || Sees(seen->second, T_cam_target)) {
          measure(target, T_cam_target);
        }
      }
    }
  }
}

// A robot's samples as its flange cameras see the world target (eye in hand): the world in the
// camera, T_cam_world = (T_world_base T_base_flange T_flange_camera)^-1, with the noise alone.
void MeasureFromFlange(const WorkcellSimulationSpec& spec, const SimulatedRobot& robot,
                       Recording* recording, Noise& noise) {
  if (robot.T_flange_camera.empty() || spec.world_target.empty()) return;
  for (const Sample& sample : recording->samples) {
    if (sample.robot != robot.name) continue;
    Pose T_base_flange;
    if (!robot.model->Forward(sample.q.data(), robot.model_values.data(), &T_base_flange)) continue;
    for (const auto& [camera, T_flange_camera] : robot.T_flange_camera) {
      const Pose T_cam_world = (robot.T_world_base * T_base_flange * T_flange_camera).inverse();
      recording->observations.push_back(
          Measure(sample.id, camera, spec.world_target, T_cam_world, spec, false, noise));
    }
  }
}

void RecordTruth(const WorkcellSimulationSpec& spec, WorkcellTruth* truth) {
  for (const auto& robot : spec.robots) {
    truth->frames[robot.name + ".base"] = {"world", robot.T_world_base};
    for (const auto& [target, pose] : robot.T_flange_target) {
      truth->frames[target] = {robot.name + ".flange", pose};
    }
    for (const auto& [camera, pose] : robot.T_flange_camera) {
      truth->frames[robot.name + "." + camera] = {robot.name + ".flange", pose};
    }
    const auto& params = robot.model->parameters();
    for (size_t i = 0; i < params.size(); ++i) {
      truth->model[robot.name + ".model." + params[i].name] = robot.model_values[i];
    }
    for (const auto* list : {&robot.effects, &spec.measurement_effects}) {
      for (const auto& e : *list) {
        const auto& effect_params = e.effect->parameters();
        for (size_t i = 0; i < effect_params.size(); ++i) {
          truth->model[e.name + "." + effect_params[i].name] = e.values[i];
        }
      }
    }
  }
  for (const auto& [camera, pose] : spec.T_world_cam) truth->frames[camera] = {"world", pose};
  for (const auto& c : spec.concealed) {
    truth->model["concealed." + c->name() + ".magnitude"] = c->size();
  }
}

}  // namespace

Recording SimulateWorkcell(const WorkcellSimulationSpec& spec, WorkcellTruth* truth) {
  std::mt19937 rng(spec.noise_seed);
  return SimulateWorkcell(spec, truth, rng);
}

Recording SimulateWorkcell(const WorkcellSimulationSpec& given, WorkcellTruth* truth,
                           std::mt19937& rng) {
  const WorkcellSimulationSpec spec = WithPoseSets(given, rng);
  Recording recording;
  recording.description =
      "simulated workcell (cellmetry simulate, seed " + std::to_string(spec.seed) + ")";
  for (const auto& [camera, pose] : spec.T_world_cam) recording.cameras.push_back(camera);
  if (!spec.world_target.empty()) recording.targets[spec.world_target] = kWorldCarrier;
  for (const auto& robot : spec.robots) {
    recording.robots[robot.name] = robot.model->num_joints();
    for (const auto& [target, pose] : robot.T_flange_target) recording.targets[target] = robot.name;
    for (const auto& [camera, pose] : robot.T_flange_camera) {
      recording.cameras.push_back(camera);
      recording.camera_mounts[camera] = robot.name;
    }
  }
  recording.samples = PlanSamples(spec);
  Noise noise{rng};
  for (const auto& robot : spec.robots) {
    MeasureRobot(spec, robot, &recording, noise);
    MeasureFromFlange(spec, robot, &recording, noise);
  }
  if (truth) RecordTruth(spec, truth);
  return recording;
}

void DrawTruth(WorkcellSimulationSpec* spec, std::mt19937& rng) {
  for (auto& robot : spec->robots) {
    robot.model_values = DrawModelTruth(*robot.model, robot.given_values, robot.errors, rng);
  }
  for (auto& [name, camera] : spec->cameras) {
    spec->T_world_cam[name] = DrawCameraTruth(camera.T_world_cam_nominal, camera.errors, rng);
  }
}

SimulatedDraw DrawAndSimulate(const WorkcellSimulationSpec& spec, std::mt19937& rng) {
  SimulatedDraw draw;
  draw.truth = spec;
  DrawTruth(&draw.truth, rng);
  draw.recording = SimulateWorkcell(draw.truth, nullptr, rng);
  return draw;
}

WorkcellEstimate TruthEstimate(const WorkcellSimulationSpec& spec) {
  WorkcellEstimate e;
  for (const auto& robot : spec.robots) {
    e.T_world_base[robot.name] = robot.T_world_base;
    e.model[robot.name] = robot.model_values;
    for (const auto& [target, pose] : robot.T_flange_target) e.T_flange_target[target] = pose;
    for (const auto& [camera, pose] : robot.T_flange_camera) {
      e.T_flange_target[robot.name + "." + camera] = pose;
    }
  }
  e.T_world_cam = spec.T_world_cam;
  return e;
}

PoseSetGeometry PoseSetGeometryOf(const WorkcellSimulationSpec& spec, const SimulatedRobot& robot,
                                  const std::string& camera_name) {
  PoseSetGeometry g;
  g.model = robot.model.get();
  g.nominal_values = robot.nominal_values;
  g.marker_mm = robot.model->nominal_tool().t;
  g.origin = robot.name;
  std::string camera = camera_name;
  if (camera.empty() && spec.cameras.size() == 1) camera = spec.cameras.begin()->first;
  const auto seen = spec.cameras.find(camera);
  if (seen == spec.cameras.end()) return g;
  g.camera_known = true;
  g.T_base_cam = robot.T_world_base.inverse() * seen->second.T_world_cam_nominal;
  g.half_fov_rad = seen->second.half_fov_rad;
  return g;
}

WorkcellProblem SimulatedProblem(const WorkcellSimulationSpec& spec, ResidualForm residual,
                                 double noise_free_sigma_mm) {
  WorkcellProblem problem;
  problem.world_target = spec.world_target;
  problem.residual = residual;
  problem.folds = 0;
  for (const auto& sim : spec.robots) {
    WorkcellRobot robot;
    robot.name = sim.name;
    robot.model = sim.model;
    robot.model_parameters = sim.model->parameters();
    for (auto& p : robot.model_parameters) p.fixed = false;
    // Without a world target the first robot's base is the world, held; the others stand in it.
    const bool world_is_base = spec.world_target.empty() && problem.robots.empty();
    robot.base.start = !spec.world_target.empty()
                           ? sim.T_world_base
                           : spec.robots.front().T_world_base.inverse() * sim.T_world_base;
    robot.base.free.fill(!world_is_base);
    if (world_is_base) robot.base_start = robot.base.start;
    for (const auto& [target, pose] : sim.T_flange_target) {
      WorkcellTool tool;
      tool.target = target;
      tool.flange_tool.start = sim.model->nominal_tool();
      problem.use_tool_rotation = problem.use_tool_rotation || !sim.point_targets.count(target);
      robot.tools.push_back(tool);
    }
    problem.robots.push_back(robot);
  }
  const Eigen::Vector3d sigma = spec.sigma_position_mm.isZero()
                                    ? Eigen::Vector3d::Constant(noise_free_sigma_mm)
                                    : spec.sigma_position_mm;
  for (const auto& [camera, pose] : spec.T_world_cam)
    problem.noise.position_sigma_mm[camera] = sigma;
  return problem;
}

void HoldModelParameters(const std::string& suffix, WorkcellProblem* problem) {
  for (auto& robot : problem->robots) {
    for (auto& p : robot.model_parameters) {
      const auto& n = p.name;
      if (n.size() >= suffix.size() &&
          n.compare(n.size() - suffix.size(), suffix.size(), suffix) == 0) {
        p.fixed = true;
      }
    }
  }
}

std::vector<SampleView> WorkcellViews(const WorkcellSimulationSpec& spec,
                                      const Recording& recording) {
  std::vector<SampleView> views;
  for (const auto& sample : recording.samples) {
    const auto robot =
        std::find_if(spec.robots.begin(), spec.robots.end(),
                     [&](const SimulatedRobot& r) { return r.name == sample.robot; });
    Pose T_base_flange;
    if (robot == spec.robots.end() ||
        !robot->model->Forward(sample.q.data(), robot->model_values.data(), &T_base_flange)) {
      continue;
    }
    for (const auto& [camera, T_world_cam] : spec.T_world_cam) {
      SampleView view{sample.id, camera, {}};
      const Pose T_cam_world = T_world_cam.inverse();
      if (!spec.world_target.empty()) view.T_cam_target[spec.world_target] = T_cam_world;
      for (const auto& [target, T_flange_target] : robot->T_flange_target) {
        view.T_cam_target[target] =
            T_cam_world * robot->T_world_base * T_base_flange * T_flange_target;
      }
      views.push_back(view);
    }
    for (const auto& [camera, T_flange_camera] : robot->T_flange_camera) {
      if (spec.world_target.empty()) break;
      SampleView view{sample.id, camera, {}};
      view.T_cam_target[spec.world_target] =
          (robot->T_world_base * T_base_flange * T_flange_camera).inverse();
      views.push_back(view);
    }
  }
  return views;
}

std::vector<std::string> CameraNames(const WorkcellSimulationSpec& spec) {
  std::vector<std::string> names;
  for (const auto& [camera, pose] : spec.T_world_cam) names.push_back(camera);
  for (const auto& robot : spec.robots) {
    for (const auto& [camera, pose] : robot.T_flange_camera) names.push_back(camera);
  }
  return names;
}

std::vector<std::string> TargetNames(const WorkcellSimulationSpec& spec) {
  std::vector<std::string> names;
  if (!spec.world_target.empty()) names.push_back(spec.world_target);
  for (const auto& robot : spec.robots) {
    for (const auto& [target, pose] : robot.T_flange_target) names.push_back(target);
  }
  return names;
}

}  // namespace cellmetry
