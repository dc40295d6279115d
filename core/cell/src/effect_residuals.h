// Residual functors of the workcell identification with effects (internal to the core).
//
// The prediction of workcell_residuals.h with the effects of effect.h in the chain:
//
//   q -> dq (joint effects, through the model's joint offsets) -> T_base_flange
//     -> flange effects (pose) -> T_cam_target -> measurement effects (position in camera)
//
// Blocks: base, tool, [camera,] robot model, then one block per effect in `effects` order.
// Evaluated with ceres::DynamicAutoDiffCostFunction: effects and robot models are templates.
#pragma once

#include <vector>

#include "cellmetry/model/effect.h"
#include "cellmetry/model/effect_context.h"
#include "workcell_residuals.h"

namespace cellmetry {

// Applies the effects of one stage to `values`; effect k's parameters are effect_params[k].
template <typename T>
void ApplyStage(EffectStage stage, const std::vector<const Effect*>& effects,
                T const* const* effect_params, const EffectContext& context, T* values) {
  for (size_t k = 0; k < effects.size(); ++k) {
    if (effects[k]->stage() == stage) effects[k]->Apply(context, effect_params[k], values);
  }
}

// A pose as a stage's values (effect.h): position, then rotation column-major.
template <typename T>
void PackPose(const Transform<T>& pose, T* values) {
  for (int i = 0; i < 3; ++i) values[i] = pose.t[i];
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) values[3 + 3 * c + r] = pose.R(r, c);
  }
}

template <typename T>
void UnpackPose(const T* values, Transform<T>* pose) {
  for (int i = 0; i < 3; ++i) pose->t[i] = values[i];
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) pose->R(r, c) = values[3 + 3 * c + r];
  }
}

// The measurement effects on a predicted target pose, position and rotation (effect.h).
template <typename T>
void ApplyMeasurement(const std::vector<const Effect*>& effects, T const* const* effect_params,
                      const EffectContext& context, Transform<T>* T_cam_target) {
  T values[12];
  PackPose(*T_cam_target, values);
  ApplyStage(EffectStage::kMeasurement, effects, effect_params, context, values);
  UnpackPose(values, T_cam_target);
}

// T_base_flange with the joint and flange effects: the joint effects' dq enters through the
// model's joint offset parameters. False where the model has no pose.
template <typename T>
bool FlangeWithEffects(const RobotModel& model, const T* model_params,
                       const std::vector<const Effect*>& effects, T const* const* effect_params,
                       const EffectContext& context, Transform<T>* T_base_flange) {
  const int n = model.num_joints();
  std::vector<T> dq(n, T(0.0));
  ApplyStage(EffectStage::kJoint, effects, effect_params, context, dq.data());
  std::vector<T> params(model_params, model_params + model.parameters().size());
  for (int j = 0; j < n; ++j) {
    const int offset = model.JointOffsetParameter(j);
    if (offset >= 0) params[offset] += dq[j];
  }
  if (!model.Forward(context.q, params.data(), T_base_flange)) return false;
  T values[12];
  PackPose(*T_base_flange, values);
  ApplyStage(EffectStage::kFlange, effects, effect_params, context, values);
  UnpackPose(values, T_base_flange);
  return true;
}

class EffectChainResidual {
 public:
  // `context` points into the sample's SampleFacts, which must outlive the residual.
  EffectChainResidual(TargetComparison comparison, FrameRefs refs, const RobotModel* model,
                      EffectContext context, bool static_camera, Pose T_cam_world_measured,
                      std::vector<const Effect*> effects)
      : comparison_(comparison), refs_(refs), model_(model), context_(context),
        static_camera_(static_camera), T_cam_world_measured_(T_cam_world_measured),
        effects_(std::move(effects)) {}

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    const int model_block = static_camera_ ? 3 : 2;
    T const* const* effect_params = blocks + model_block + 1;
    Transform<T> T_base_flange;
    if (!FlangeWithEffects(*model_, blocks[model_block], effects_, effect_params, context_,
                           &T_base_flange)) {
      return false;
    }
    const Transform<T> T_cam_world = static_camera_ ? CameraFromWorld(blocks[2], refs_.world_cam)
                                                    : T_cam_world_measured_.cast<T>();
    Transform<T> predicted = T_cam_world * FrameFromBlock(blocks[0], refs_.world_base) *
                             T_base_flange * FrameFromBlock(blocks[1], refs_.flange_target);
    ApplyMeasurement(effects_, effect_params, context_, &predicted);
    comparison_.Compare(predicted, residual);
    return true;
  }

 private:
  TargetComparison comparison_;
  FrameRefs refs_;
  const RobotModel* model_;
  EffectContext context_;
  bool static_camera_;
  Pose T_cam_world_measured_;
  std::vector<const Effect*> effects_;
};

// A static camera's view of the world target, through the measurement effects.
// Blocks: camera, then one per effect.
class WorldEffectResidual {
 public:
  WorldEffectResidual(TargetComparison comparison, Eigen::Matrix3d R_ref_camera,
                      EffectContext context, std::vector<const Effect*> effects)
      : comparison_(comparison), R_ref_camera_(R_ref_camera), context_(context),
        effects_(std::move(effects)) {}

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    Transform<T> predicted = CameraFromWorld(blocks[0], R_ref_camera_);
    ApplyMeasurement(effects_, blocks + 1, context_, &predicted);
    comparison_.Compare(predicted, residual);
    return true;
  }

 private:
  TargetComparison comparison_;
  Eigen::Matrix3d R_ref_camera_;
  EffectContext context_;
  std::vector<const Effect*> effects_;
};

}  // namespace cellmetry
