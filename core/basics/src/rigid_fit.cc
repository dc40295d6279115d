// Closed-form rigid fit: Eigen's Umeyama (1991) without scale, after the checks a fit needs.
#include "cellmetry/basics/rigid_fit.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace cellmetry {
namespace {

// Whether the points span at least a line's worth of directions: two non-negligible principal
// spreads (all points on one line leave the rotation about that line undetermined).
bool SpansAPlane(const Eigen::Matrix3Xd& points) {
  const Eigen::Matrix3Xd centred = points.colwise() - points.rowwise().mean();
  const Eigen::Matrix3d scatter = centred * centred.transpose();
  const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
  return spread[1] > 1e-9 * std::max(1.0, spread[2]);
}

}  // namespace

std::optional<Pose> FitRigidTransform(const std::vector<Eigen::Vector3d>& from,
                                      const std::vector<Eigen::Vector3d>& to) {
  const size_t n = from.size();
  if (n < 3 || to.size() != n) return std::nullopt;
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (size_t i = 0; i < n; ++i) {
    src.col(i) = from[i];
    dst.col(i) = to[i];
  }
  if (!src.allFinite() || !dst.allFinite()) return std::nullopt;
  if (!SpansAPlane(src) || !SpansAPlane(dst)) return std::nullopt;
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, /*with_scaling=*/false);
  Pose pose;
  pose.R = T.topLeftCorner<3, 3>();
  pose.t = T.topRightCorner<3, 1>();
  return pose;
}

}  // namespace cellmetry
