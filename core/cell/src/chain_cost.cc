#include "chain_cost.h"

#include "cellmetry/basics/so3_jacobians.h"
#include "frame_cache.h"

namespace cellmetry {
namespace {

using BlockJacobian = Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>>;

// Writes [dt | dr], each row scaled by 1/sigma, if Ceres asked for this block.
void Store(double* jacobian, const Eigen::Matrix3d& d_translation,
           const Eigen::Matrix3d& d_rotation, const Eigen::Vector3d& inv_sigma) {
  if (jacobian == nullptr) return;
  BlockJacobian J(jacobian);
  J.leftCols<3>() = inv_sigma.asDiagonal() * d_translation;
  J.rightCols<3>() = inv_sigma.asDiagonal() * d_rotation;
}

}  // namespace

ChainCost::ChainCost(TargetComparison comparison, FrameRefs refs, ChainBlocks blocks,
                     const Pose& T_base_flange, const Pose& T_cam_world_fixed)
    : ChainCost(comparison, std::make_shared<const FrameRefs>(std::move(refs)), blocks,
                T_base_flange, T_cam_world_fixed) {}

ChainCost::ChainCost(TargetComparison comparison, std::shared_ptr<const FrameRefs> refs,
                     ChainBlocks blocks, const Pose& T_base_flange, const Pose& T_cam_world_fixed)
    : comparison_(comparison), blocks_(blocks), T_base_flange_(T_base_flange),
      refs_(std::move(refs)) {
  if (!blocks.camera) {
    T_world_cam_fixed_ = std::make_unique<const Pose>(T_cam_world_fixed.inverse());
  }
  set_num_residuals(3);
  for (bool is_block : {blocks.base, blocks.tool, blocks.camera}) {
    if (is_block) mutable_parameter_block_sizes()->push_back(6);
  }
}

bool ChainCost::Evaluate(double const* const* parameters, double* residuals,
                         double** jacobians) const {
  int k = 0;
  const double* base = blocks_.base ? parameters[k++] : nullptr;
  const double* tool = blocks_.tool ? parameters[k++] : nullptr;
  const double* camera = blocks_.camera ? parameters[k++] : nullptr;
  // The frames every residual shares, each made once per thread for these values (frame_cache.h).
  const bool with_jacobian = jacobians != nullptr;
  CachedFrame base_frame, tool_frame, camera_frame;
  if (base) base_frame = FrameOfBlock(base, refs_->world_base, with_jacobian);
  if (tool) tool_frame = FrameOfBlock(tool, refs_->flange_target, with_jacobian);
  if (camera) camera_frame = FrameOfBlock(camera, refs_->world_cam, with_jacobian);
  const Pose T_world_base = base ? base_frame.T : Pose::Identity();
  const Pose T_flange_target = tool ? tool_frame.T : Pose::Identity();
  const Pose T_world_cam = camera ? camera_frame.T : *T_world_cam_fixed_;
  const Eigen::Matrix3d R_cw = T_world_cam.R.transpose();
  const Pose T_world_flange = T_world_base * T_base_flange_;
  const Eigen::Vector3d p_world = T_world_flange * T_flange_target.t;
  const Eigen::Vector3d& inv_sigma = comparison_.inv_sigma();
  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();

  Eigen::Vector3d error;
  if (comparison_.compared() == Compared::kPosition) {
    error = R_cw * (p_world - T_world_cam.t) - comparison_.measured().t;
  } else {
    const Eigen::Matrix3d R_cam_target = R_cw * T_world_flange.R * T_flange_target.R;
    error = RotationError<double>(R_cam_target, comparison_.measured().R);
  }
  Eigen::Map<Eigen::Vector3d> residual(residuals);
  residual = error.cwiseProduct(inv_sigma);
  if (jacobians == nullptr) return true;

  k = 0;
  if (comparison_.compared() == Compared::kPosition) {
    if (base) {
      Store(jacobians[k++], R_cw,
            -R_cw * Skew(p_world - T_world_base.t) * base_frame.J_left, inv_sigma);
    }
    if (tool) Store(jacobians[k++], R_cw * T_world_flange.R, zero, inv_sigma);
    if (camera) {
      Store(jacobians[k++], -R_cw,
            R_cw * Skew(p_world - T_world_cam.t) * camera_frame.J_left, inv_sigma);
    }
  } else {
    // A left perturbation Exp(d) of a factor rotates the prediction by Exp(R d) in the camera
    // frame, with R the rotation from that factor's left frame to the camera.
    const Eigen::Matrix3d d_error = InverseLeftJacobian(error);
    if (base) {
      Store(jacobians[k++], zero, d_error * R_cw * base_frame.J_left, inv_sigma);
    }
    if (tool) {
      Store(jacobians[k++], zero,
            d_error * R_cw * T_world_flange.R * tool_frame.J_left, inv_sigma);
    }
    if (camera) {
      Store(jacobians[k++], zero, -d_error * R_cw * camera_frame.J_left, inv_sigma);
    }
  }
  return true;
}

}  // namespace cellmetry
