// The prediction chain with effects (effect.h), written once for double and Jet: what the
// identification's residuals (core/cell), the simulator and compensation (core/compensation)
// all evaluate, so that a fit, its simulated truth and the commands computed from it agree.
//
//   q -> dq (joint effects, through the model's joint offsets) -> T_base_flange
//     -> flange effects (pose) -> ... -> measurement effects (a target's pose in a camera)
//
// Effect k's parameters are effect_params[k]; an effect acts only at its own stage.
#pragma once

#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/model/effect.h"
#include "cellmetry/model/robot_model.h"

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

}  // namespace cellmetry
