// The image of a circle's centre, from the ellipse its outline projects to (perspective
// eccentricity correction).
//
// A tilted circle projects to an ellipse whose centre is not the image of the circle's centre:
// the nearer half looks bigger. With the camera's intrinsics the ellipse and the optical centre
// define a cone; its circular sections follow from the cone's eigen-decomposition
// (Q = V diag(l1, l2, l3) V^T, l1 >= l2 > 0 > l3: Q - l2 I factors into two planes, and each plane
// parallel to one of them cuts the cone in a circle; Shiu and Ahmad, IEEE T-RA 5(5), 1989;
// Safaee-Rad et al., IEEE T-RA 8(5), 1992). The known radius fixes the distance. Two planes, so
// two circles, fit every ellipse: one image cannot tell which half of the dot is nearer. The
// caller picks one with an approximate normal (the dot plugin's `dot_normal` option, or the pose
// the 13-dot pattern's homography gives).
//
// The centre's image direction does not depend on the radius (only its depth does), so a wrong
// diameter_mm does not bias the corrected pixel.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "dot_common/ellipse_fit.h"
#include "dot_common/image_geometry.h"

namespace cellmetry::dot {

struct Circle3d {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  // camera frame
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // out of the printed side (toward the camera)
};

// The two circles of `radius_mm` that project to `conic` (normalised image coordinates,
// x^T Q x = 0 with x = (x/z, y/z, 1)); nullopt unless the conic is a real ellipse.
std::optional<std::array<Circle3d, 2>> CirclesFromConic(const Eigen::Matrix3d& conic,
                                                        double radius_mm);

// The ellipse (fitted in ideal pixels) as a conic in normalised image coordinates.
Eigen::Matrix3d NormalisedConic(const Ellipse& ellipse, const ImageGeometry& geometry);

// The circle whose normal is nearest `normal_hint` (camera frame), or nullopt.
std::optional<Circle3d> CircleNearest(const Ellipse& ellipse, const ImageGeometry& geometry,
                                      double radius_mm, const Eigen::Vector3d& normal_hint);

}  // namespace cellmetry::dot
