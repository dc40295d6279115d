// Euler angles: three turns about coordinate axes, to and from a rotation matrix.
//
// Contract: angles in radians; R maps coordinates in the turned frame into the reference frame.
// `axes` names the axes in the order written (0 = x, 1 = y, 2 = z), any of the 12 sequences
// with no axis twice in a row (six Tait-Bryan: XYZ ..., six proper Euler: XYX ...):
//   intrinsic  R = R_1(a) R_2(b) R_3(c)  (each turn about the already turned frame's axis)
//   extrinsic  R = R_3(c) R_2(b) R_1(a)  (each turn about the fixed frame's axis)
// Extrinsic (i, j, k) by (a, b, c) is intrinsic (k, j, i) by (c, b, a). The import reads
// tables in either (import/rotation_conventions.h); the angle check (cell) reads a rotation back
// into its angles to try the other convention.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>

namespace cellmetry {

// "XYZ" -> {0, 1, 2}; none unless it is one of the 12 Euler sequences (no axis twice in a row).
std::optional<std::array<int, 3>> ParseEulerOrder(const std::string& order);

// The elementary rotation about axis 0 = x, 1 = y, 2 = z.
Eigen::Matrix3d AxisRotation(int axis, double angle_rad);

Eigen::Matrix3d EulerToRotation(const std::array<int, 3>& axes, bool intrinsic,
                                const Eigen::Vector3d& angles_rad);

// The angles of R: the middle one in [-pi/2, pi/2] for Tait-Bryan sequences, [0, pi] for proper
// Euler ones; at gimbal lock (the first and last axes coincide) the last angle is zero.
// EulerToRotation(RotationToEuler(R)) == R to rounding.
Eigen::Vector3d RotationToEuler(const std::array<int, 3>& axes, bool intrinsic,
                                const Eigen::Matrix3d& R);

}  // namespace cellmetry
