// Plane-to-image homography by the normalised direct linear transform (Hartley and Zisserman,
// "Multiple View Geometry", 2nd ed., algorithm 4.2): both point sets centred and scaled to mean
// distance sqrt(2), then the null vector of the 2n x 9 system.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace cellmetry::dot {

// H with image ~ H (plane x, plane y, 1); nullopt for fewer than 4 points or a degenerate set.
std::optional<Eigen::Matrix3d> FitHomography(const std::vector<Eigen::Vector2d>& plane,
                                             const std::vector<Eigen::Vector2d>& image);

Eigen::Vector2d ApplyHomography(const Eigen::Matrix3d& h, const Eigen::Vector2d& p);

}  // namespace cellmetry::dot
