// Closed-form rigid fit: Eigen's Umeyama (1991) without scale, after the checks a fit needs.
#include "cellmetry/basics/rigid_fit.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace cellmetry {
namespace {

bool SpansAPlane(const Eigen::Matrix3Xd& points) {
  const Eigen::Matrix3Xd centred = points.colwise() - points.rowwise().mean();
  return ScatterSpansAPlane(centred * centred.transpose());
}

}  // namespace

bool ScatterSpansAPlane(const Eigen::Matrix3d& scatter) {
  const Eigen::Vector3d spread =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
  return spread[1] > 1e-9 * std::max(1.0, spread[2]);
}

Eigen::Matrix3d RotationOfCrossCovariance(const Eigen::Matrix3d& cross) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d sign = Eigen::Vector3d::Ones();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) sign[2] = -1.0;
  return svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
}

std::optional<Pose> FitRigidTransform(const std::vector<Eigen::Vector3d>& from,
                                      const std::vector<Eigen::Vector3d>& to) {
  const size_t n = from.size();
  if (n < 3 || to.size() != n) return std::nullopt;
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (size_t i = 0; i < n; ++i) {
    src.col(static_cast<Eigen::Index>(i)) = from[i];
    dst.col(static_cast<Eigen::Index>(i)) = to[i];
  }
  if (!src.allFinite() || !dst.allFinite() || !SpansAPlane(src) || !SpansAPlane(dst)) {
    return std::nullopt;
  }
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, /*with_scaling=*/false);
  Pose pose;
  pose.R = T.topLeftCorner<3, 3>();
  pose.t = T.topRightCorner<3, 1>();
  return pose;
}

}  // namespace cellmetry
