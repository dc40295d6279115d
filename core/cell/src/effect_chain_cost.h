// EffectChainCost: the workcell residual with effects (workcell_residuals.h) with analytic
// derivatives, effects at every stage (joint, flange, measurement).
//
//   P = T_cam_world * T_world_base * T_base_flange(model, joint and flange effects)
//         * T_flange_target                                         (target in camera)
//   r = Compare(Measure(P, measurement effect parameters))
//
// Every parameter but the measurement effects' acts through P, so the Jacobian factors through
// a small motion of P, a shift s and a turn w in the camera frame (P.t + s, Exp(w) P.R):
//
//   dr / d(frame, model, joint or flange effect parameter) = dr/d(s, w) * d(s, w)/d(parameter)
//
// dr/d(s, w) and the measurement effects' columns come from Jets over 6 + (effect parameters)
// directions on the measurement stage and the comparison alone; d(s, w)/d(parameter) is closed
// form for the frame blocks (as in chain_cost.h) and the model (its flange twists,
// RobotModel::ForwardWithTwists; the model's closed form where it has one); the joint and flange
// effects' come from Jets over their own stage (effect_stage_linearization.h) carried on by the
// model's joint-offset twists and the flange stage's motion map. Jets over the whole chain
// instead (EffectChainResidual, kept as the reference the tests compare with) run a UR3's
// forward kinematics seven times per residual for its 30 parameters and the three frames: the
// input-uncertainty linearization of exp_a spent most of its time there, and the physics
// finder's refits with a joint effect three quarters of theirs. Checked against central
// differences and those Jets in tests/test_chain_cost.cc.
//
// Blocks that predict the same measured pose (the repeated captures of one robot pose by one
// static camera; every world-tag observation of one camera) share it as shared_prediction_cost.h
// says: Predict is the chain and the measurement effects, whose tangent (the measured position,
// or a left rotation of the measured rotation in the camera) the same Jets carry instead of the
// comparison; Compare is TargetComparison's. The Problem then evaluates the chain once for all
// of them (exp_a: once per ten captures). Assembly shares only where the effects read nothing
// that differs from capture to capture (time, temperature, payload, approach).
#pragma once

#include <memory>
#include <vector>

#include "cellmetry/estimation/shared_prediction_cost.h"
#include "cellmetry/model/effect.h"
#include "effect_stage_linearization.h"
#include "forward_memo.h"
#include "workcell_residuals.h"

namespace cellmetry {

// The effects in one chain (a robot's own and every measurement effect, or the measurement
// effects alone) and their parameter counts, shared by every cost over them: a copy per cost
// was most of what assembling exp_a's 22,500 effect costs took.
struct ChainEffectList {
  ChainEffectList(std::vector<const Effect*> effects, std::vector<int> sizes);
  std::vector<const Effect*> effects;
  std::vector<int> sizes;  // each effect's parameter count (its block's size)
  int num_params = 0;      // their sum
};

class EffectChainCost final : public SharedPredictionCost {
 public:
  // `model` not null: a carried target, blocks base, tool, [camera,] model, one per effect
  // (EffectChainResidual's). `model` null: the world target seen by a static camera, blocks
  // camera, one per effect (WorldEffectResidual's). `refs` and `effects` are shared by the
  // costs over the same frame blocks and effects. `context` points into the sample's
  // SampleFacts, which must outlive the cost.
  // `forward`: the capture's forward kinematics shared with its other blocks (forward_memo.h;
  // null: each evaluation runs the chain itself). `same_as`: an earlier EffectChainCost that
  // predicts the same measured pose (the same frames, joints, camera, target, effects and
  // compared quantity, and a context that differs in nothing the effects read), whose key this
  // one takes; it must outlive this one's use in a Problem.
  EffectChainCost(TargetComparison comparison, std::shared_ptr<const FrameRefs> refs,
                  const RobotModel* model, EffectContext context, bool static_camera,
                  const Pose& T_cam_world_measured, std::shared_ptr<const ChainEffectList> effects,
                  std::shared_ptr<ForwardMemo> forward = nullptr,
                  const EffectChainCost* same_as = nullptr);
  // A block on its own (tests).
  EffectChainCost(TargetComparison comparison, FrameRefs refs, const RobotModel* model,
                  EffectContext context, bool static_camera, const Pose& T_cam_world_measured,
                  std::vector<const Effect*> effects, const std::vector<int>& effect_sizes);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const void* prediction_key() const override { return key_; }
  // The measured pose (after the measurement effects); its tangent is the position (mm, camera
  // axes) or a left rotation about the camera axes (rad), as compared.
  bool Predict(double const* const* parameters, Pose* prediction,
               double** tangent_jacobians) const override;
  void Compare(const Pose& prediction, double* residual,
               Eigen::Matrix3d* d_residual) const override;
  bool AffineComparison(Eigen::Vector3d* weight, Eigen::Vector3d* measured) const override {
    return comparison_.Affine(weight, measured);
  }

 private:
  // What the last Jet stage yields: the residual (Evaluate) or the measured pose's tangent
  // (Predict).
  enum class Output { kResidual, kTangent };
  // Evaluate and Predict: `values` (3) and, per asked block, d values / d block; with kTangent
  // also the measured pose.
  bool Linearize(double const* const* parameters, Output output, double* values, Pose* measured,
                 double** jacobians) const;
  // The prediction P and what its motion (s, w) does per frame, model and effect parameter.
  struct Chain;
  // `with_jacobians`: the frames' left Jacobians too (StoreFrameJacobians); `effect_twists`:
  // the flange's motion per joint and flange effect parameter.
  bool PredictChain(double const* const* parameters, bool with_twists, bool with_jacobians,
                    bool effect_twists, Chain* chain) const;
  // T_base_flange through the joint stage, the model and the flange stage; with `with_twists`
  // the model's flange twists after the flange stage, with `effect_twists` the effects'.
  bool FlangeOfModel(const double* model_params, double const* const* effect_params,
                     bool with_twists, bool effect_twists, Chain* chain) const;
  // d(s, w of P) / d(flange twist in the base frame).
  static Eigen::Matrix<double, 6, 6> FlangeToCamera(const Chain& chain);
  // r and dr/d(s, w, effect parameters) at P; the effects' directions only where asked for.
  // With kTangent the measured pose's tangent (and the pose) instead of r.
  void MeasureAndCompare(const Pose& P, double const* const* effect_params, bool effects_asked,
                         Output output, double* values, Pose* measured,
                         Eigen::Matrix<double, 3, Eigen::Dynamic>* H) const;
  // The last Jet stage: r, or the tangent of `moved` about `measured` (its values).
  void LastStage(const Transform<Jet>& moved, Output output, const Pose& measured, Jet* out) const;
  void StoreFrameJacobians(const Chain& chain, const Eigen::Matrix<double, 3, 6>& H_motion,
                           double** jacobians) const;

  TargetComparison comparison_;
  std::shared_ptr<const FrameRefs> refs_;
  const RobotModel* model_;
  EffectContext context_;
  bool static_camera_;
  Pose T_world_cam_fixed_;
  std::shared_ptr<const ChainEffectList> list_;
  const std::vector<const Effect*>& effects_;  // list_'s
  const std::vector<int>& effect_sizes_;       // list_'s
  int first_effect_ = 0;                       // block index of the first effect
  int num_effect_params_ = 0;
  bool joint_effects_ = false, flange_effects_ = false;  // a carried target's chain has them
  std::shared_ptr<ForwardMemo> forward_;
  const void* key_;  // this cost, or the one it predicts the same as
};

}  // namespace cellmetry
