// PinholeCamera: a calibrated camera with OpenCV's distortion model (Brown-Conrady: k1 k2 p1 p2
// k3), in OpenCV's pixel convention. Project() is templated for autodiff; Ray() inverts the
// distortion by Newton's method (to 1e-9 px across the frame, tested with strong barrel
// distortion). Calibration files (ours, OpenCV's, ROS camera_info) are read by camera_file.h.
#pragma once

#include <array>
#include <string>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

template <typename T>
using Vector2 = Eigen::Matrix<T, 2, 1>;

struct PinholeCamera {
  int width = 0;
  int height = 0;
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  std::array<double, 5> distortion{};  // k1 k2 p1 p2 k3

  // Pixel of a point in the camera frame (z > 0).
  template <typename T>
  Vector2<T> Project(const Vector3<T>& p) const {
    const T x = p.x() / p.z(), y = p.y() / p.z();
    const Vector2<T> d = Distort(Vector2<T>(x, y));
    return Vector2<T>(T(fx) * d.x() + T(cx), T(fy) * d.y() + T(cy));
  }

  // Normalised image coordinates (x/z, y/z) -> distorted normalised coordinates.
  template <typename T>
  Vector2<T> Distort(const Vector2<T>& n) const {
    const auto& [k1, k2, p1, p2, k3] = distortion;
    const T& x = n.x();
    const T& y = n.y();
    const T r2 = x * x + y * y;
    const T radial = T(1) + r2 * (T(k1) + r2 * (T(k2) + r2 * T(k3)));
    return Vector2<T>(x * radial + T(2 * p1) * x * y + T(p2) * (r2 + T(2) * x * x),
                      y * radial + T(p1) * (r2 + T(2) * y * y) + T(2 * p2) * x * y);
  }

  // Unit-z ray (x, y, 1) through a pixel, distortion removed.
  Eigen::Vector3d Ray(const Eigen::Vector2d& pixel) const;

  // Why an image of width x height cannot be from this camera ("" when it can).
  std::string SizeMismatch(int image_width, int image_height) const {
    if (image_width == width && image_height == height) return "";
    return "image is " + std::to_string(image_width) + "x" + std::to_string(image_height) +
           ", the calibration is for " + std::to_string(width) + "x" + std::to_string(height);
  }

  bool Contains(const Eigen::Vector2d& pixel) const {
    return pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() < width - 0.5 &&
           pixel.y() < height - 0.5;
  }
};

// An OAK-D-like camera: 1280 x 800, f = 880 px, no distortion (the report's rig).
PinholeCamera OakDLikeCamera();

}  // namespace cellmetry
