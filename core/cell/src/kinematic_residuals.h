// Residual functors of the kinematic calibration (internal to the core), evaluated with
// ceres::DynamicAutoDiffCostFunction over the blocks (camera 6, marker 3, robot model n).
// See kinematic_problem.h for the two formulations.
#pragma once

#include "cellmetry/model/frame_block.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

// Cartesian: (T_cam_base * (FK(q).t + FK(q).R * marker) - p_measured) / sigma, camera axes.
class ForwardPointResidual {
 public:
  ForwardPointResidual(const RobotModel* model, std::vector<double> q,
                       const Eigen::Vector3d& p_cam_mm, const Eigen::Vector3d& sigma_mm,
                       const Eigen::Matrix3d& R_ref_base_cam)
      : model_(model), q_(std::move(q)), p_cam_(p_cam_mm), inv_sigma_(sigma_mm.cwiseInverse()),
        R_ref_(R_ref_base_cam) {}

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    const Transform<T> T_base_cam = FrameFromBlock(blocks[0], R_ref_);
    const Vector3<T> marker(blocks[1][0], blocks[1][1], blocks[1][2]);
    Transform<T> flange;
    if (!model_->Forward(q_.data(), blocks[2], &flange)) return false;
    const Vector3<T> p_cam = T_base_cam.inverse() * (flange.t + flange.R * marker);
    for (int i = 0; i < 3; ++i) residual[i] = (p_cam[i] - T(p_cam_[i])) * T(inv_sigma_[i]);
    return true;
  }

 private:
  const RobotModel* model_;
  std::vector<double> q_;
  Eigen::Vector3d p_cam_;
  Eigen::Vector3d inv_sigma_;
  Eigen::Matrix3d R_ref_;
};

// Joint space: W * (IK(T_base_cam * p_measured - marker) - q_command). The flange only translates
// (models with inverse kinematics), so the marker offset is a plain translation in the base frame.
class InversePointResidual {
 public:
  InversePointResidual(const RobotModel* model, std::vector<double> q,
                       const Eigen::Vector3d& p_cam_mm, const Eigen::Matrix3d& whitening,
                       const Eigen::Matrix3d& R_ref_base_cam)
      : model_(model), q_(std::move(q)), p_cam_(p_cam_mm), W_(whitening), R_ref_(R_ref_base_cam) {}

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    const Transform<T> T_base_cam = FrameFromBlock(blocks[0], R_ref_);
    const Vector3<T> marker(blocks[1][0], blocks[1][1], blocks[1][2]);
    const Vector3<T> flange = T_base_cam * p_cam_.cast<T>() - marker;
    T q[3];
    if (!model_->Inverse(flange.data(), blocks[2], q)) return false;
    Vector3<T> dq;
    for (int i = 0; i < 3; ++i) dq[i] = q[i] - T(q_[i]);
    const Vector3<T> r = W_.cast<T>() * dq;
    for (int i = 0; i < 3; ++i) residual[i] = r[i];
    return true;
  }

 private:
  const RobotModel* model_;
  std::vector<double> q_;
  Eigen::Vector3d p_cam_;
  Eigen::Matrix3d W_;
  Eigen::Matrix3d R_ref_;
};

}  // namespace cellmetry
