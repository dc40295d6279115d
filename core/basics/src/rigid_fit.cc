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

RigidFitOnto::RigidFitOnto(const std::vector<Eigen::Vector3d>& to) : to_(3, to.size()) {
  for (size_t i = 0; i < to.size(); ++i) to_.col(static_cast<Eigen::Index>(i)) = to[i];
  usable_ = to.size() >= 3 && to_.allFinite() && SpansAPlane(to_);
}

std::optional<Pose> RigidFitOnto::Fit(const std::vector<Eigen::Vector3d>& from) const {
  const size_t n = from.size();
  if (!usable_ || n != static_cast<size_t>(to_.cols())) return std::nullopt;
  Eigen::Matrix3Xd src(3, n);
  for (size_t i = 0; i < n; ++i) src.col(static_cast<Eigen::Index>(i)) = from[i];
  if (!src.allFinite() || !SpansAPlane(src)) return std::nullopt;
  const Eigen::Matrix4d T = Eigen::umeyama(src, to_, /*with_scaling=*/false);
  Pose pose;
  pose.R = T.topLeftCorner<3, 3>();
  pose.t = T.topRightCorner<3, 1>();
  return pose;
}

std::optional<Pose> FitRigidTransform(const std::vector<Eigen::Vector3d>& from,
                                      const std::vector<Eigen::Vector3d>& to) {
  return RigidFitOnto(to).Fit(from);
}

}  // namespace cellmetry
