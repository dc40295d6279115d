#include "cellmetry/cell/workcell_assembly.h"

#include "cellmetry/basics/error.h"
#include "chain_cost.h"
#include "effect_residuals.h"
#include "workcell_residuals.h"

namespace cellmetry {
namespace {

Pose ObservedPose(const Observation& obs) {
  return Pose{obs.rvec ? RotationFromRvec(obs.rvec->data()) : Eigen::Matrix3d::Identity(),
              obs.position_mm};
}

// Frame block starting at `start`: translation as values, rotation as R_ref.
int AddFrameBlock(AssembledWorkcell* out, const std::string& name, FrameBlockSpec spec,
                  const Pose& start) {
  spec.start = start;
  const int id = out->problem.AddBlock(name, FrameParameters(spec));
  out->R_ref[id] = start.R;
  return id;
}

}  // namespace

// Effect facts of every robot's samples, at each robot's nominal model.
std::vector<SampleFacts> GatherAllFacts(const WorkcellProblem& spec, const Recording& recording) {
  std::vector<SampleFacts> all(recording.samples.size());
  for (const auto& robot : spec.robots) {
    std::vector<double> nominal;
    for (const auto& p : robot.model_parameters) nominal.push_back(p.nominal);
    std::vector<SampleFacts> facts = GatherSampleFacts(recording, robot.name, *robot.model, nominal);
    for (size_t i = 0; i < facts.size(); ++i) {
      if (recording.samples[i].robot == robot.name) all[i] = std::move(facts[i]);
    }
  }
  return all;
}

WorkcellData PrepareWorkcellData(const WorkcellProblem& spec, const Recording& recording) {
  WorkcellData data;
  // target -> (robot index, tool index)
  std::map<std::string, std::pair<int, int>> carried;
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    for (size_t t = 0; t < spec.robots[r].tools.size(); ++t) {
      carried[spec.robots[r].tools[t].target] = {static_cast<int>(r), static_cast<int>(t)};
    }
  }
  // (sample, camera) -> world target observations, for the per-frame model.
  std::map<std::pair<int, std::string>, std::vector<const Observation*>> world_seen;
  for (size_t i = 0; i < recording.observations.size(); ++i) {
    const Observation& obs = recording.observations[i];
    if (obs.target != spec.world_target) continue;
    if (!obs.rvec) {
      ++data.skipped["world target without rotation"];
      continue;
    }
    data.world_observations.push_back(static_cast<int>(i));
    world_seen[{obs.sample, obs.camera}].push_back(&obs);
  }
  for (size_t i = 0; i < recording.observations.size(); ++i) {
    const Observation& obs = recording.observations[i];
    if (obs.target == spec.world_target) continue;
    const auto it = carried.find(obs.target);
    if (it == carried.end()) {
      ++data.skipped["target '" + obs.target + "' is not identified by this job"];
      continue;
    }
    ToolMeasurement m;
    m.observation = static_cast<int>(i);
    m.sample_index = recording.SampleIndex(obs.sample);
    m.robot = it->second.first;
    m.tool = it->second.second;
    const Sample& sample = recording.samples[m.sample_index];
    if (sample.robot != spec.robots[m.robot].name) {
      throw InputError({recording.folder + "/observations.csv", obs.line, 0},
                       "target '" + obs.target + "' is carried by robot '" +
                           spec.robots[m.robot].name + "' but sample " +
                           std::to_string(obs.sample) + " is a state of robot '" + sample.robot +
                           "'",
                       "Point the observation at a sample of the robot that carries the target");
    }
    if (spec.use_tool_rotation && !obs.rvec) {
      ++data.skipped["tool observation without rotation"];
      continue;
    }
    const auto world = world_seen.find({obs.sample, obs.camera});
    if (world != world_seen.end()) {
      // Several captures of the world target in one sample: use their mean pose.
      std::vector<Eigen::Matrix3d> rotations;
      Eigen::Vector3d position = Eigen::Vector3d::Zero();
      for (const auto* w : world->second) {
        rotations.push_back(RotationFromRvec(w->rvec->data()));
        position += w->position_mm;
      }
      m.has_world_pose = true;
      m.T_cam_world = Pose{MeanRotation(rotations),
                           position / static_cast<double>(world->second.size())};
    } else if (spec.camera_model == CameraModel::kPerFrame) {
      ++data.skipped["no world target in the same capture (per-frame model)"];
      continue;
    }
    data.tools.push_back(m);
  }
  if (data.tools.empty()) {
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
  if (!spec.effects.empty()) data.facts = GatherAllFacts(spec, recording);
  return data;
}

std::unique_ptr<AssembledWorkcell> AssembleWorkcell(const WorkcellProblem& spec,
                                                    const Recording& recording,
                                                    const WorkcellData& data,
                                                    const NoiseModel& noise,
                                                    const WorkcellEstimate& start,
                                                    const std::set<int>& poses) {
  auto out = std::make_unique<AssembledWorkcell>();
  const bool static_cameras = spec.camera_model == CameraModel::kStaticCameras;
  for (const auto& robot : spec.robots) {
    out->base_block.push_back(AddFrameBlock(out.get(), robot.name + ".base", robot.base,
                                            start.T_world_base.at(robot.name)));
    std::vector<Parameter> model_params = robot.model_parameters;
    const auto& values = start.model.at(robot.name);
    for (size_t i = 0; i < model_params.size(); ++i) model_params[i].nominal = values[i];
    out->model_block.push_back(out->problem.AddBlock(robot.name + ".model", model_params));
    std::vector<int> tools;
    for (const auto& tool : robot.tools) {
      tools.push_back(AddFrameBlock(out.get(), tool.target, tool.flange_tool,
                                    start.T_flange_target.at(tool.target)));
    }
    out->tool_block.push_back(tools);
  }
  if (static_cameras) {
    FrameBlockSpec camera_spec;
    camera_spec.free.fill(true);
    camera_spec.description = "camera pose in the world";
    for (const auto& [camera, T_world_cam] : start.T_world_cam) {
      out->camera_block[camera] = AddFrameBlock(out.get(), camera, camera_spec, T_world_cam);
    }
  }
  for (const WorkcellEffect& e : spec.effects) {
    std::vector<Parameter> params = e.effect->parameters();
    const auto values = start.effects.find(e.name);
    for (size_t i = 0; i < params.size(); ++i) {
      params[i].nominal = values != start.effects.end() ? values->second.at(i) : 0.0;
    }
    out->effect_block.push_back(out->problem.AddBlock(e.name, params));
  }
  // The effects in a robot's chain (its own and every measurement effect), and their blocks.
  auto chain_effects = [&](const std::string& robot, std::vector<const Effect*>* effects,
                           std::vector<int>* blocks) {
    for (size_t k = 0; k < spec.effects.size(); ++k) {
      const WorkcellEffect& e = spec.effects[k];
      if (e.effect->stage() == EffectStage::kMeasurement || e.robot == robot) {
        effects->push_back(e.effect.get());
        blocks->push_back(out->effect_block[k]);
      }
    }
  };

  auto info_for = [&](int observation, ResidualInfo::Kind kind, const Eigen::Vector3d& sigma) {
    const Observation& obs = recording.observations[observation];
    ResidualInfo info;
    info.kind = kind;
    info.observation = observation;
    info.sample = obs.sample;
    info.pose = recording.samples[recording.SampleIndex(obs.sample)].pose;
    info.camera = obs.camera;
    info.target = obs.target;
    info.sigma = sigma;
    return info;
  };

  for (const ToolMeasurement& m : data.tools) {
    const Sample& sample = recording.samples[m.sample_index];
    if (!poses.empty() && !poses.count(sample.pose)) continue;
    const Observation& obs = recording.observations[m.observation];
    const WorkcellRobot& robot = spec.robots[m.robot];
    const bool model_free = [&] {
      for (const auto& p : out->problem.block_parameters(out->model_block[m.robot])) {
        if (!p.fixed) return true;
      }
      return false;
    }();
    const int base = out->base_block[m.robot];
    const int tool = out->tool_block[m.robot][m.tool];
    const int camera = static_cameras ? out->camera_block.at(obs.camera) : -1;
    FrameRefs refs;
    refs.world_base = out->R_ref.at(base);
    refs.flange_target = out->R_ref.at(tool);
    if (static_cameras) refs.world_cam = out->R_ref.at(camera);
    const TargetNoise& sigma = noise.at(obs.camera, obs.target);

    std::vector<Compared> compared = {Compared::kPosition};
    if (spec.use_tool_rotation) compared.push_back(Compared::kRotation);
    for (Compared c : compared) {
      const bool position = c == Compared::kPosition;
      TargetComparison comparison(c, ObservedPose(obs),
                                  position ? sigma.position_mm : sigma.rotation_rad);
      std::unique_ptr<ceres::CostFunction> cost;
      std::vector<int> blocks = {base, tool};
      if (static_cameras) blocks.push_back(camera);
      std::vector<const Effect*> effects;
      std::vector<int> effect_blocks;
      chain_effects(robot.name, &effects, &effect_blocks);
      if (!effects.empty()) {
        const SampleFacts& facts = data.facts.at(m.sample_index);
        EffectContext context = ContextOf(facts, spec.gravity_base, obs.camera);
        context.target = obs.target;
        auto* functor = new EffectChainResidual(comparison, refs, robot.model.get(), context,
                                                static_cameras, m.T_cam_world, effects);
        auto* dynamic = new ceres::DynamicAutoDiffCostFunction<EffectChainResidual, kJetStride>(
            functor);
        blocks.push_back(out->model_block[m.robot]);
        blocks.insert(blocks.end(), effect_blocks.begin(), effect_blocks.end());
        for (int b : blocks) dynamic->AddParameterBlock(out->problem.block_parameters(b).size());
        dynamic->SetNumResiduals(3);
        cost.reset(dynamic);
      } else if (model_free) {
        auto* functor = new ModelChainResidual(comparison, refs, robot.model.get(), sample.q,
                                               static_cameras, m.T_cam_world);
        auto* dynamic = new ceres::DynamicAutoDiffCostFunction<ModelChainResidual, kJetStride>(
            functor);
        blocks.push_back(out->model_block[m.robot]);
        for (int b : blocks) dynamic->AddParameterBlock(out->problem.block_parameters(b).size());
        dynamic->SetNumResiduals(3);
        cost.reset(dynamic);
      } else {
        Pose T_base_flange;
        if (!robot.model->Forward(sample.q.data(), start.model.at(robot.name).data(),
                                  &T_base_flange)) {
          throw InputError({recording.folder + "/samples.csv", 0, 0},
                           "robot '" + robot.name + "' has no pose for sample " +
                               std::to_string(sample.id),
                           "Check the joint values against the robot model");
        }
        const ChainBlocks chain{/*base=*/true, /*tool=*/true, /*camera=*/static_cameras};
        cost = std::make_unique<ChainCost>(comparison, refs, chain, T_base_flange, m.T_cam_world);
      }
      out->problem.AddResidual(
          std::move(cost), blocks,
          info_for(m.observation,
                   position ? ResidualInfo::Kind::kPosition : ResidualInfo::Kind::kRotation,
                   position ? sigma.position_mm : sigma.rotation_rad));
    }
  }

  if (static_cameras) {
    for (int index : data.world_observations) {
      const Observation& obs = recording.observations[index];
      const Sample& sample = recording.samples[recording.SampleIndex(obs.sample)];
      if (!poses.empty() && !poses.count(sample.pose)) continue;
      const int camera = out->camera_block.at(obs.camera);
      const TargetNoise& sigma = noise.at(obs.camera, obs.target);
      for (Compared c : {Compared::kPosition, Compared::kRotation}) {
        const bool position = c == Compared::kPosition;
        TargetComparison comparison(c, ObservedPose(obs),
                                    position ? sigma.position_mm : sigma.rotation_rad);
        std::vector<const Effect*> effects;
        std::vector<int> blocks = {camera};
        for (size_t k = 0; k < spec.effects.size(); ++k) {
          if (spec.effects[k].effect->stage() != EffectStage::kMeasurement) continue;
          effects.push_back(spec.effects[k].effect.get());
          blocks.push_back(out->effect_block[k]);
        }
        std::unique_ptr<ceres::CostFunction> cost;
        if (!effects.empty()) {
          EffectContext context;
          context.camera = obs.camera;
          context.target = obs.target;
          auto* dynamic = new ceres::DynamicAutoDiffCostFunction<WorldEffectResidual, kJetStride>(
              new WorldEffectResidual(comparison, out->R_ref.at(camera), context, effects));
          for (int b : blocks) dynamic->AddParameterBlock(out->problem.block_parameters(b).size());
          dynamic->SetNumResiduals(3);
          cost.reset(dynamic);
        } else {
          FrameRefs refs;
          refs.world_cam = out->R_ref.at(camera);
          const ChainBlocks camera_only{/*base=*/false, /*tool=*/false, /*camera=*/true};
          cost = std::make_unique<ChainCost>(comparison, refs, camera_only, Pose::Identity(),
                                             Pose::Identity());
        }
        out->problem.AddResidual(
            std::move(cost), blocks,
            info_for(index, position ? ResidualInfo::Kind::kPosition
                                     : ResidualInfo::Kind::kRotation,
                     position ? sigma.position_mm : sigma.rotation_rad));
      }
    }
  }
  out->problem.Build();
  return out;
}

WorkcellEstimate ReadEstimate(const WorkcellProblem& spec, const AssembledWorkcell& assembled) {
  WorkcellEstimate estimate;
  const Problem& problem = assembled.problem;
  auto frame = [&](int block) {
    return FrameFromBlock(problem.values(block), assembled.R_ref.at(block));
  };
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    const auto& robot = spec.robots[r];
    estimate.T_world_base[robot.name] = frame(assembled.base_block[r]);
    const int model = assembled.model_block[r];
    estimate.model[robot.name].assign(problem.values(model),
                                      problem.values(model) + robot.model_parameters.size());
    for (size_t t = 0; t < robot.tools.size(); ++t) {
      estimate.T_flange_target[robot.tools[t].target] = frame(assembled.tool_block[r][t]);
    }
  }
  for (const auto& [camera, block] : assembled.camera_block) {
    estimate.T_world_cam[camera] = frame(block);
  }
  for (size_t k = 0; k < spec.effects.size(); ++k) {
    const int block = assembled.effect_block[k];
    estimate.effects[spec.effects[k].name].assign(
        problem.values(block), problem.values(block) + problem.block_parameters(block).size());
  }
  return estimate;
}

}  // namespace cellmetry
