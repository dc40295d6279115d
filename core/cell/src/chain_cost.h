// ChainCost: the workcell residual with analytic derivatives, for a held robot model.
//
// Predicts the target pose in the camera frame through
//
//   T_cam_target = T_cam_world * T_world_base * T_base_flange * T_flange_target
//
// where T_base_flange is a constant (the robot model at the sample's joints) and each of
// T_world_base, T_flange_target, T_world_cam is either a 6-parameter frame block (frame_block.h)
// or a constant. The residual is TargetComparison's: position (mm) or rotation (rad), over sigma.
//
// The Jacobian is closed form (derivation in docs/internals.md, "Analytic workcell
// Jacobian"): with p_w the target position in the world and J_l the SO(3) left Jacobian,
//   d p_cam / d t_base = R_cw          d p_cam / d r_base = -R_cw [p_w - t_wb]x J_l(r_base)
//   d p_cam / d t_tool = R_cw R_wf     d p_cam / d t_cam  = -R_cw
//   d p_cam / d r_cam  =  R_cw [p_w - t_wc]x J_l(r_cam)
//   d e_rot / d r_x    =  J_l^-1(e_rot) * (rotation of the perturbation into the camera frame)
// split as SharedPredictionCost asks: Predict's tangent Jacobian is the position's, or the
// perturbation's rotation into the camera frame; Compare's is 1/sigma, times J_l^-1(e_rot).
// It replaces Ceres autodiff on the hot path (BM_Identify/exp_a 2.5x faster end to end) and is
// checked against central differences in tests/test_chain_cost.cc.
//
// Blocks that read the same frames at the same joints predict the same pose (every capture of one
// robot pose by one camera; every world-tag observation of one static camera): assembly makes
// the first such ChainCost, and each later one names it as the cost it predicts the same as; the
// Problem evaluates the prediction once for all of them (shared_prediction_cost.h).
#pragma once

#include <memory>

#include "cellmetry/estimation/shared_prediction_cost.h"
#include "workcell_residuals.h"

namespace cellmetry {

// Which factors of the chain are parameter blocks, in block order (base, tool, camera).
struct ChainBlocks {
  bool base = true;
  bool tool = true;
  bool camera = true;
};

class ChainCost final : public SharedPredictionCost {
 public:
  // Constants stand in for the factors that are not blocks: T_base_flange always,
  // T_cam_world_fixed when !blocks.camera. Without base and tool blocks the target is the
  // world frame itself (the world target seen by a static camera). `refs` is shared by every
  // block over the same frame blocks: an evaluation streams through all of a cell's blocks,
  // and what each one holds is what it reads from memory. `same_as`: an earlier ChainCost
  // that predicts the same (the same frames, joints and compared quantity), whose key this
  // one takes; it must outlive this one's use in a Problem (both are the Problem's).
  ChainCost(TargetComparison comparison, std::shared_ptr<const FrameRefs> refs, ChainBlocks blocks,
            const Pose& T_base_flange, const Pose& T_cam_world_fixed,
            const ChainCost* same_as = nullptr);
  // A block on its own (tests).
  ChainCost(TargetComparison comparison, FrameRefs refs, ChainBlocks blocks,
            const Pose& T_base_flange, const Pose& T_cam_world_fixed);

  const void* prediction_key() const override { return key_; }
  // The predicted T_cam_target; the tangent is the position's coordinates (mm, camera axes) or
  // a left rotation of the prediction about the camera axes (rad).
  bool Predict(double const* const* parameters, Pose* prediction,
               double** tangent_jacobians) const override;
  void Compare(const Pose& prediction, double* residual,
               Eigen::Matrix3d* d_residual) const override;
  bool AffineComparison(Eigen::Vector3d* weight, Eigen::Vector3d* measured) const override {
    return comparison_.Affine(weight, measured);
  }
  // The same as SharedPredictionCost's, without the virtual calls and with D A on the 3 x 6
  // blocks at fixed size: Ceres evaluates each block on its own, 160,000 of them per iteration
  // on bench_scale's factory cell.
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  // The chain at the blocks' values: what the prediction and its Jacobian are made of.
  struct State;
  void MakeState(double const* const* parameters, bool with_jacobian, State* state) const;
  // The compared quantity of the predicted T_cam_target (the other is left as it is).
  void PredictionOf(const State& state, Pose* prediction) const;
  // Per asked block, L times d tangent / d block (L: the identity for Predict, dr / d tangent
  // for Evaluate, applied to the few 3 x 3 factors rather than to the 3 x 6 results).
  void StoreJacobians(const State& state, const Eigen::Matrix3d& L, double** jacobians) const;

  TargetComparison comparison_;
  ChainBlocks blocks_;
  Pose T_base_flange_;
  std::shared_ptr<const FrameRefs> refs_;
  // The measured camera where it is not a block (the per-frame model); not held otherwise: the
  // objects' size is what an evaluation reads.
  std::unique_ptr<const Pose> T_world_cam_fixed_;
  const void* key_;  // this cost, or the one it predicts the same as
};

}  // namespace cellmetry
