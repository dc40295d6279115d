// The cell's Jet cost functions (jet_costs.h), in a translation unit of their own.
#include "jet_costs.h"

#include "eye_in_hand_residual.h"
#include "joint_space_residual.h"

namespace cellmetry {
std::unique_ptr<ceres::CostFunction> JointSpaceCostFunction(
    const FrameRefs& refs, const RobotModel* model, const std::vector<double>& q,
    const Eigen::Vector3d& p_cam_mm, const Eigen::Matrix3d& whitening, const Problem& problem,
    const std::vector<int>& blocks) {
  return OnJets(new JointSpaceResidual(refs, model, q, p_cam_mm, whitening), problem, blocks);
}

std::unique_ptr<ceres::CostFunction> EyeInHandCostFunction(
    const TargetComparison& comparison, const Eigen::Matrix3d& R_ref_world_base,
    const Eigen::Matrix3d& R_ref_flange_camera, const RobotModel* model,
    const std::vector<double>& q, const Problem& problem, const std::vector<int>& blocks) {
  return OnJets(new EyeInHandResidual(comparison, R_ref_world_base, R_ref_flange_camera, model, q),
                problem, blocks);
}

}  // namespace cellmetry
