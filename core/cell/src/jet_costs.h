// The cell's Jet cost functions, each built in jet_costs.cc: a translation unit of its own, so
// that the compiler's inlining budget goes to their Jet arithmetic (in the assembly's large unit
// it did not, and a delta calibration ran 1.4x slower).
#pragma once

#include <memory>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/dynamic_autodiff_cost_function.h>

#include "cellmetry/estimation/problem.h"
#include "workcell_residuals.h"

namespace cellmetry {

// Wraps a Jet functor over `blocks` of `problem` (3 residuals).
template <typename Functor>
std::unique_ptr<ceres::CostFunction> OnJets(Functor* functor, const Problem& problem,
                                            const std::vector<int>& blocks) {
  auto* cost = new ceres::DynamicAutoDiffCostFunction<Functor, kJetStride>(functor);
  for (int b : blocks) cost->AddParameterBlock(problem.block_parameters(b).size());
  cost->SetNumResiduals(3);
  return std::unique_ptr<ceres::CostFunction>(cost);
}

// EyeInHandResidual (eye_in_hand_residual.h) over `blocks` of `problem`: base, the camera's
// frame on the flange, model.
std::unique_ptr<ceres::CostFunction> EyeInHandCostFunction(
    const TargetComparison& comparison, const Eigen::Matrix3d& R_ref_world_base,
    const Eigen::Matrix3d& R_ref_flange_camera, const RobotModel* model,
    const std::vector<double>& q, const Problem& problem, const std::vector<int>& blocks);

// JointSpaceResidual (joint_space_residual.h) over `blocks` of `problem`.
std::unique_ptr<ceres::CostFunction> JointSpaceCostFunction(
    const FrameRefs& refs, const RobotModel* model, const std::vector<double>& q,
    const Eigen::Vector3d& p_cam_mm, const Eigen::Matrix3d& whitening, const Problem& problem,
    const std::vector<int>& blocks);

}  // namespace cellmetry
