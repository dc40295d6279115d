// One frame seen from another, with first-order covariance (relative_pose.h).
#include "cellmetry/basics/relative_pose.h"

namespace cellmetry {
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

}  // namespace

Eigen::Matrix<double, 6, 12> RelativePoseJacobian(const Pose& T_world_a, const Pose& T_world_b) {
  const Eigen::Matrix3d Rt = T_world_a.R.transpose();
  Eigen::Matrix<double, 6, 12> J = Eigen::Matrix<double, 6, 12>::Zero();
  J.block<3, 3>(0, 0) = -Rt;                                   // dt_a
  J.block<3, 3>(0, 3) = Rt * Skew(T_world_b.t - T_world_a.t);  // dphi_a
  J.block<3, 3>(0, 6) = Rt;                                    // dt_b
  J.block<3, 3>(3, 3) = -Rt;                                   // dphi_a
  J.block<3, 3>(3, 9) = Rt;                                    // dphi_b
  return J;
}

RelativePose PoseInFrame(const Pose& T_world_a, const Pose& T_world_b,
                         const Eigen::Matrix<double, 12, 12>& covariance_ab) {
  const Eigen::Matrix<double, 6, 12> J = RelativePoseJacobian(T_world_a, T_world_b);
  return {T_world_a.inverse() * T_world_b, J * covariance_ab * J.transpose()};
}

}  // namespace cellmetry
