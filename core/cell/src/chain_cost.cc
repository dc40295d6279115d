// ChainCost (chain_cost.h): the chain predicted in closed form, then compared.
#include "chain_cost.h"

#include <stdexcept>

#include "cellmetry/basics/so3_jacobians.h"
#include "frame_cache.h"

namespace cellmetry {
namespace {

using TangentJacobian = Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>>;

// Writes [dt | dr] of the tangent if it was asked for this block.
void Store(double* jacobian, const Eigen::Matrix3d& d_translation,
           const Eigen::Matrix3d& d_rotation) {
  if (jacobian == nullptr) return;
  TangentJacobian J(jacobian);
  J.leftCols<3>() = d_translation;
  J.rightCols<3>() = d_rotation;
}

}  // namespace

ChainCost::ChainCost(TargetComparison comparison, std::shared_ptr<const FrameRefs> refs,
                     ChainBlocks blocks, const Pose& T_base_flange, const Pose& T_cam_world_fixed,
                     const ChainCost* same_as)
    : comparison_(comparison), blocks_(blocks), T_base_flange_(T_base_flange),
      refs_(std::move(refs)), key_(same_as ? same_as->key_ : this) {
  if (same_as && same_as->comparison_.compared() != comparison_.compared()) {
    throw std::logic_error("ChainCost: a position and a rotation cannot share a prediction");
  }
  if (!blocks.camera) {
    T_world_cam_fixed_ = std::make_unique<const Pose>(T_cam_world_fixed.inverse());
  }
  for (bool is_block : {blocks.base, blocks.tool, blocks.camera}) {
    if (is_block) mutable_parameter_block_sizes()->push_back(6);
  }
}

ChainCost::ChainCost(TargetComparison comparison, FrameRefs refs, ChainBlocks blocks,
                     const Pose& T_base_flange, const Pose& T_cam_world_fixed)
    : ChainCost(comparison, std::make_shared<const FrameRefs>(std::move(refs)), blocks,
                T_base_flange, T_cam_world_fixed) {}

bool ChainCost::Predict(double const* const* parameters, Pose* prediction,
                        double** tangent_jacobians) const {
  int k = 0;
  const double* base = blocks_.base ? parameters[k++] : nullptr;
  const double* tool = blocks_.tool ? parameters[k++] : nullptr;
  const double* camera = blocks_.camera ? parameters[k++] : nullptr;
  // The frames every residual shares, each made once per thread for these values (frame_cache.h).
  const bool with_jacobian = tangent_jacobians != nullptr;
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
  const bool position = comparison_.compared() == Compared::kPosition;
  if (position) {
    prediction->t = R_cw * (p_world - T_world_cam.t);
  } else {
    prediction->R = R_cw * T_world_flange.R * T_flange_target.R;
  }
  if (!with_jacobian) return true;

  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  k = 0;
  if (position) {
    if (base) {
      Store(tangent_jacobians[k++], R_cw,
            -R_cw * Skew(p_world - T_world_base.t) * base_frame.J_left);
    }
    if (tool) Store(tangent_jacobians[k++], R_cw * T_world_flange.R, zero);
    if (camera) {
      Store(tangent_jacobians[k++], -R_cw,
            R_cw * Skew(p_world - T_world_cam.t) * camera_frame.J_left);
    }
    return true;
  }
  // A left perturbation Exp(d) of a factor rotates the prediction by Exp(R d) in the camera
  // frame, with R the rotation from that factor's left frame to the camera.
  if (base) Store(tangent_jacobians[k++], zero, R_cw * base_frame.J_left);
  if (tool) Store(tangent_jacobians[k++], zero, R_cw * T_world_flange.R * tool_frame.J_left);
  if (camera) Store(tangent_jacobians[k++], zero, -R_cw * camera_frame.J_left);
  return true;
}

void ChainCost::Compare(const Pose& prediction, double* residual,
                        Eigen::Matrix3d* d_residual) const {
  const Eigen::Vector3d& inv_sigma = comparison_.inv_sigma();
  Eigen::Map<Eigen::Vector3d> r(residual);
  if (comparison_.compared() == Compared::kPosition) {
    r = (prediction.t - comparison_.measured().t).cwiseProduct(inv_sigma);
    if (d_residual) *d_residual = inv_sigma.asDiagonal();
    return;
  }
  const Eigen::Vector3d error = RotationError<double>(prediction.R, comparison_.measured().R);
  r = error.cwiseProduct(inv_sigma);
  if (d_residual) *d_residual = inv_sigma.asDiagonal() * InverseLeftJacobian(error);
}

bool ChainCost::Evaluate(double const* const* parameters, double* residuals,
                         double** jacobians) const {
  Pose prediction;
  if (!ChainCost::Predict(parameters, &prediction, jacobians)) return false;
  Eigen::Matrix3d D;
  ChainCost::Compare(prediction, residuals, jacobians ? &D : nullptr);
  if (jacobians == nullptr) return true;
  const int num_blocks = static_cast<int>(parameter_block_sizes().size());
  for (int k = 0; k < num_blocks; ++k) {
    if (jacobians[k] == nullptr) continue;
    TangentJacobian J(jacobians[k]);
    const Eigen::Matrix<double, 3, 6> A = J;
    J.noalias() = D * A;
  }
  return true;
}

}  // namespace cellmetry
