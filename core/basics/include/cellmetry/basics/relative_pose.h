// One identified frame seen from another (a robot's base from another robot's base), with its
// uncertainty propagated from both frames' to first order, their correlation included.
//
// Both frames are given in the world. A frame's error is a shift dt of its origin and a small
// rotation dphi about the world's axes, T_world_x -> (Exp(dphi) R, t + dt), the way result.json
// states a frame's sigma (x y z mm, rx ry rz rad). Then T_a_b = T_world_a^-1 T_world_b,
// t_ab = R_a^T (t_b - t_a), R_ab = R_a^T R_b, and its error, with the rotation about a's axes
// (the new parent's, as every frame in cellmetry states it):
//
//   d t_ab   = R_a^T (dt_b - dt_a + [t_b - t_a]x dphi_a)
//   d phi_ab = R_a^T (dphi_b - dphi_a)
//
// exact to first order (tests/test_exports.cc checks it against central differences).
#pragma once

#include <Eigen/Core>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// d(t_ab, phi_ab) / d(dt_a, dphi_a, dt_b, dphi_b): 6 x 12.
Eigen::Matrix<double, 6, 12> RelativePoseJacobian(const Pose& T_world_a, const Pose& T_world_b);

struct RelativePose {
  Pose T_a_b;
  Matrix6d covariance;  // of (t mm, phi rad) about a's axes
};

// `covariance_ab`: 12 x 12 of (dt_a, dphi_a, dt_b, dphi_b).
RelativePose PoseInFrame(const Pose& T_world_a, const Pose& T_world_b,
                         const Eigen::Matrix<double, 12, 12>& covariance_ab);

}  // namespace cellmetry
