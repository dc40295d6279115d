// Rotation helpers of transform.h: the nearest rotation to a matrix by SVD (det = +1), and the
// chordal mean of rotations as the rotation nearest to their sum.
#include "cellmetry/basics/transform.h"

#include <Eigen/SVD>

namespace cellmetry {

Eigen::Matrix3d ProjectToRotation(const Eigen::Matrix3d& M) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

Eigen::Matrix3d MeanRotation(const std::vector<Eigen::Matrix3d>& rotations) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (const auto& R : rotations) sum += R;
  return ProjectToRotation(sum);
}

}  // namespace cellmetry
