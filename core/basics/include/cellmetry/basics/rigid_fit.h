// Closed-form rigid fit between matched point sets (Kabsch 1976; Umeyama 1991 without scale).
//
// FitRigidTransform returns T_to_from minimising sum |to_i - T * from_i|^2 (Eigen::umeyama). It
// needs at least three finite points that are not all on one line; otherwise std::nullopt.
#pragma once

#include <optional>
#include <vector>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

// Whether points with this scatter (the sum of their centred outer products) span at least a
// plane: two non-negligible principal spreads (on one line, the rotation about it is free).
bool ScatterSpansAPlane(const Eigen::Matrix3d& scatter);

// The proper rotation R maximising trace(R^T cross) for cross = sum (to_i - to_mean)
// (from_i - from_mean)^T: the rotation of the rigid fit from `from` onto `to` (Umeyama 1991,
// eq. 39-40, as Eigen::umeyama computes it).
Eigen::Matrix3d RotationOfCrossCovariance(const Eigen::Matrix3d& cross);

std::optional<Pose> FitRigidTransform(const std::vector<Eigen::Vector3d>& from,
                                      const std::vector<Eigen::Vector3d>& to);

}  // namespace cellmetry
