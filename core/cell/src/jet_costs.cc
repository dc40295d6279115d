// The cell's Jet cost functions (jet_costs.h), in a translation unit of their own.
#include "jet_costs.h"

#include "joint_space_residual.h"

namespace cellmetry {
std::unique_ptr<ceres::CostFunction> JointSpaceCostFunction(const FrameRefs& refs,
                                                           const RobotModel* model,
                                                           const std::vector<double>& q,
                                                           const Eigen::Vector3d& p_cam_mm,
                                                           const Eigen::Matrix3d& whitening,
                                                           const Problem& problem,
                                                           const std::vector<int>& blocks) {
  return OnJets(new JointSpaceResidual(refs, model, q, p_cam_mm, whitening), problem, blocks);
}

}  // namespace cellmetry
