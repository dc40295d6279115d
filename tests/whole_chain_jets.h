// The workcell residual with effects as Jets over the whole chain: the reference that
// tests/test_chain_cost.cc checks the analytic EffectChainCost (core/cell/src/effect_chain_cost.h)
// against, term by term. It is the chain written the plain way, once, for double and Jet:
//
//   q -> dq (joint effects, through the model's joint offsets) -> T_base_flange
//     -> flange effects (pose) -> T_cam_target -> measurement effects (position in camera)
//
// Blocks: base, tool, [camera,] robot model, then one block per effect in `effects` order.
// Evaluated with ceres::DynamicAutoDiffCostFunction. The identification used it until every
// effect stage had a closed-form motion: it runs the forward kinematics once per
// kJetStride parameters of the whole chain.
#pragma once

#include <vector>

#include "cellmetry/model/effect.h"
#include "cellmetry/model/effect_chain.h"
#include "cellmetry/model/effect_context.h"
#include "workcell_residuals.h"

namespace cellmetry {

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
