// Where the ellipse is fitted. A circle's image is exactly an ellipse only in an undistorted
// pinhole image, so with a calibrated camera the edge points are moved to "ideal" pixels
// (the same camera without lens distortion, camera.h Ray()) before the fit, and the centre is
// moved back; without a camera (or with zero distortion) both maps are the identity.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "cellmetry/model/camera.h"

namespace cellmetry::dot {

class ImageGeometry {
 public:
  ImageGeometry() = default;
  explicit ImageGeometry(std::optional<PinholeCamera> camera);

  const std::optional<PinholeCamera>& camera() const { return camera_; }
  bool distorted() const { return distorted_; }

  // Distorted image pixel -> ideal pixel (fx x + cx, fy y + cy of the undistorted ray).
  Eigen::Vector2d ToIdeal(const Eigen::Vector2d& pixel) const;
  // Ideal pixel -> distorted image pixel.
  Eigen::Vector2d ToImage(const Eigen::Vector2d& ideal) const;
  // d(ideal) / d(image pixel) at a pixel (central differences; identity without distortion).
  Eigen::Matrix2d IdealJacobian(const Eigen::Vector2d& pixel) const;
  // Ideal pixel -> normalised image coordinates (x / z, y / z, 1) and back.
  Eigen::Matrix3d IdealFromNormalised() const;

 private:
  std::optional<PinholeCamera> camera_;
  bool distorted_ = false;
};

}  // namespace cellmetry::dot
