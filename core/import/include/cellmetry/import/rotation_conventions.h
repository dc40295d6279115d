// Rotation conventions a table may write a rotation in, to and from a rotation matrix.
//
// Contract: every function here works in radians and on a rotation matrix R that maps
// coordinates in the rotated frame into the reference frame (for an observation, R_camera_target).
// Converting the table's angle unit is the caller's business (angles are multiplied by their
// unit's factor before they come here).
//
//   euler            three angles about the axes of `order` (any of the 12: XYZ, XZY, YXZ, YZX,
//                    ZXY, ZYX, XYX, XZX, YXY, YZY, ZXZ, ZYZ), in the order written:
//                    intrinsic  R = R_1(a) R_2(b) R_3(c)  (each turn about the turned frame's axis)
//                    extrinsic  R = R_3(c) R_2(b) R_1(a)  (each turn about the fixed frame's axis)
//   rpy              roll about x, pitch about y, yaw about z, about fixed axes:
//                    R = R_z(yaw) R_y(pitch) R_x(roll)  (= extrinsic XYZ = intrinsic ZYX
//                    with the angles reversed; ROS and URDF)
//   quaternion       Hamilton's, w the scalar part, written wxyz or xyzw; must be unit to within
//                    a tolerance, then normalised (q and -q are the same rotation)
//   rotation_vector  axis times angle (OpenCV's rvec)
//   matrix           3x3, row-major; must be orthonormal with determinant +1 to within a
//                    tolerance, then projected onto the nearest rotation
//
// To... functions refuse nothing: they return a problem in words, empty when the values are a
// rotation, so that the caller can name the file, line and column.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>

#include "cellmetry/basics/euler_angles.h"  // ParseEulerOrder, EulerToRotation, ...

namespace cellmetry {

enum class RotationKind { kEuler, kRollPitchYaw, kQuaternion, kRotationVector, kMatrix };

struct RotationConvention {
  RotationKind kind = RotationKind::kRotationVector;
  std::array<int, 3> euler_axes = {0, 1, 2};  // euler: 0 = x, 1 = y, 2 = z, in the order written
  bool intrinsic = true;                      // euler: turned axes (true) or fixed axes (false)
  bool scalar_first = true;                   // quaternion: wxyz (true) or xyzw (false)
  double tolerance = 1e-3;  // quaternion: | |q| - 1 |; matrix: max |R^T R - I| entry

  // Numbers a rotation takes in this convention: 3, 4 (quaternion) or 9 (matrix).
  int value_count() const;
  // Whether the values are angles (converted by the table's angle unit).
  bool values_are_angles() const;
  // "euler XYZ intrinsic", "quaternion xyzw", ...: for messages.
  std::string Describe() const;
};

// R from `values` (value_count() of them, angles in rad). `problem` is set (and R is still the
// nearest rotation, or identity when there is none) when the values are not a rotation.
Eigen::Matrix3d ToRotation(const RotationConvention& convention, const double* values,
                           std::string* problem);

// The values of R in `convention` (angles in rad): euler and rpy with the middle angle in
// [-pi/2, pi/2] (proper Euler sequences: [0, pi]), quaternion with w >= 0, rotation vector with
// angle in [0, pi], matrix row-major. ToRotation(FromRotation(R)) == R to rounding.
std::array<double, 9> FromRotation(const RotationConvention& convention, const Eigen::Matrix3d& R);

}  // namespace cellmetry
