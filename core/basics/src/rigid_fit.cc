#include "cellmetry/basics/rigid_fit.h"

#include <Eigen/SVD>

namespace cellmetry {

std::optional<Pose> FitRigidTransform(const std::vector<Eigen::Vector3d>& from,
                                      const std::vector<Eigen::Vector3d>& to) {
  const size_t n = from.size();
  if (n < 3 || to.size() != n) return std::nullopt;
  Eigen::Vector3d mean_from = Eigen::Vector3d::Zero(), mean_to = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    mean_from += from[i];
    mean_to += to[i];
  }
  mean_from /= static_cast<double>(n);
  mean_to /= static_cast<double>(n);
  Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();  // sum (to_i - mean)(from_i - mean)^T
  for (size_t i = 0; i < n; ++i) cross += (to[i] - mean_to) * (from[i] - mean_from).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d s = svd.singularValues();
  // All points on one line (or one point): the rotation about that line is undetermined.
  if (s[1] <= 1e-9 * std::max(1.0, s[0])) return std::nullopt;
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  Pose T;
  T.R = svd.matrixU() * D * svd.matrixV().transpose();
  T.t = mean_to - T.R * mean_from;
  return T;
}

}  // namespace cellmetry
