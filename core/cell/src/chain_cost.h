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
// The Jacobian is closed form (derivation in docs/architecture.md, "Analytic workcell
// Jacobian"): with p_w the target position in the world and J_l the SO(3) left Jacobian,
//   d p_cam / d t_base = R_cw          d p_cam / d r_base = -R_cw [p_w - t_wb]x J_l(r_base)
//   d p_cam / d t_tool = R_cw R_wf     d p_cam / d t_cam  = -R_cw
//   d p_cam / d r_cam  =  R_cw [p_w - t_wc]x J_l(r_cam)
//   d e_rot / d r_x    =  J_l^-1(e_rot) * (rotation of the perturbation into the camera frame)
// It replaces Ceres autodiff on the hot path (BM_Identify/exp_a 2.5x faster end to end) and is
// checked against central differences in tests/test_chain_cost.cc.
#pragma once

#include <ceres/cost_function.h>

#include <memory>

#include "workcell_residuals.h"

namespace cellmetry {

// Which factors of the chain are parameter blocks, in block order (base, tool, camera).
struct ChainBlocks {
  bool base = true;
  bool tool = true;
  bool camera = true;
};

class ChainCost : public ceres::CostFunction {
 public:
  // Constants stand in for the factors that are not blocks: T_base_flange always,
  // T_cam_world_fixed when !blocks.camera. Without base and tool blocks the target is the
  // world frame itself (the world target seen by a static camera).
  ChainCost(TargetComparison comparison, FrameRefs refs, ChainBlocks blocks,
            const Pose& T_base_flange, const Pose& T_cam_world_fixed);
  // The same with `refs` shared by every block that reads the same frame blocks: an
  // evaluation streams through all of a cell's blocks, and a copy each (424 bytes, more than
  // half the object) was most of what it read from memory (exp_a: 22,500 blocks, 18 MB).
  ChainCost(TargetComparison comparison, std::shared_ptr<const FrameRefs> refs,
            ChainBlocks blocks, const Pose& T_base_flange, const Pose& T_cam_world_fixed);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  TargetComparison comparison_;
  ChainBlocks blocks_;
  Pose T_base_flange_;
  std::shared_ptr<const FrameRefs> refs_;
  // The measured camera where it is not a block (the per-frame model); not held otherwise: the
  // objects' size is what an evaluation reads.
  std::unique_ptr<const Pose> T_world_cam_fixed_;
};

}  // namespace cellmetry
