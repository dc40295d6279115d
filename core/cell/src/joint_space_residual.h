// The joint-space residual of a carried target's measured position (internal to the cell layer;
// workcell_problem.h, ResidualForm::kJointSpace):
//
//   r = W (IK(T_world_base^-1 T_world_cam p_measured - t_flange_target) - q_command)
//
// For robots whose flange only translates (position inverse kinematics: a delta arm), so the
// tool offset is a plain translation in the base frame. Blocks as JetChainLayout says ([base,]
// [tool,] camera, robot model); evaluated on Jets with ceres::DynamicAutoDiffCostFunction.
#pragma once

#include "cellmetry/model/frame_block.h"
#include "cellmetry/model/robot_model.h"
#include "workcell_residuals.h"

namespace cellmetry {

class JointSpaceResidual {
 public:
  JointSpaceResidual(FrameRefs refs, const RobotModel* model, std::vector<double> q,
                     const Eigen::Vector3d& p_cam_mm, const Eigen::Matrix3d& whitening)
      : refs_(refs), model_(model), q_(std::move(q)), p_cam_(p_cam_mm), W_(whitening),
        layout_(JetChainLayout::Of(refs_, /*static_camera=*/true)) {}

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    const Vector3<T> tool = layout_.ToolOrigin(blocks, refs_);
    const Vector3<T> p_world =
        FrameBlockMapFixedPoint(blocks[layout_.camera], refs_.world_cam, p_cam_);
    const Vector3<T> flange = layout_.BaseFromWorld(blocks, refs_, p_world) - tool;
    T q[3];
    if (!model_->Inverse(flange.data(), blocks[layout_.model], q)) return false;
    T dq[3];
    for (int i = 0; i < 3; ++i) dq[i] = q[i] - q_[i];
    for (int i = 0; i < 3; ++i)
      residual[i] = W_(i, 0) * dq[0] + W_(i, 1) * dq[1] + W_(i, 2) * dq[2];
    return true;
  }

 private:
  FrameRefs refs_;
  const RobotModel* model_;
  std::vector<double> q_;
  Eigen::Vector3d p_cam_;
  Eigen::Matrix3d W_;
  JetChainLayout layout_;
};

// W with W^T W = (J Sigma J^T)^-1: whitens a joint error by the measurement noise `sigma_mm`
// (camera axes) propagated through J = d q / d p_cam.
inline Eigen::Matrix3d JointWhitening(const Eigen::Matrix3d& J, const Eigen::Vector3d& sigma_mm) {
  const Eigen::Matrix3d cov = J * sigma_mm.cwiseAbs2().asDiagonal() * J.transpose();
  const Eigen::Matrix3d L = Eigen::LLT<Eigen::Matrix3d>(cov).matrixL();
  return L.inverse();
}

}  // namespace cellmetry
