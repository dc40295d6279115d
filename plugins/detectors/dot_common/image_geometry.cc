// ImageGeometry (image_geometry.h): distorted <-> ideal pixels through the camera's Ray() and
// Project(), the identity without a camera or distortion.
#include "dot_common/image_geometry.h"

#include <Eigen/Dense>

namespace cellmetry::dot {

ImageGeometry::ImageGeometry(std::optional<PinholeCamera> camera) : camera_(std::move(camera)) {
  if (camera_) {
    for (double k : camera_->distortion) distorted_ = distorted_ || k != 0.0;
  }
}

Eigen::Vector2d ImageGeometry::ToIdeal(const Eigen::Vector2d& pixel) const {
  if (!distorted_) return pixel;
  const Eigen::Vector3d ray = camera_->Ray(pixel);
  return Eigen::Vector2d(camera_->fx * ray.x() + camera_->cx, camera_->fy * ray.y() + camera_->cy);
}

Eigen::Vector2d ImageGeometry::ToImage(const Eigen::Vector2d& ideal) const {
  if (!distorted_) return ideal;
  const Eigen::Vector3d ray((ideal.x() - camera_->cx) / camera_->fx,
                            (ideal.y() - camera_->cy) / camera_->fy, 1.0);
  return camera_->Project(ray);
}

Eigen::Matrix2d ImageGeometry::IdealJacobian(const Eigen::Vector2d& pixel) const {
  if (!distorted_) return Eigen::Matrix2d::Identity();
  constexpr double h = 0.5;
  Eigen::Matrix2d j;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d d = Eigen::Vector2d::Unit(k) * h;
    j.col(k) = (ToIdeal(pixel + d) - ToIdeal(pixel - d)) / (2.0 * h);
  }
  return j;
}

Eigen::Matrix3d ImageGeometry::IdealFromNormalised() const {
  Eigen::Matrix3d k = Eigen::Matrix3d::Identity();
  if (camera_) k << camera_->fx, 0, camera_->cx, 0, camera_->fy, camera_->cy, 0, 0, 1;
  return k;
}

}  // namespace cellmetry::dot
