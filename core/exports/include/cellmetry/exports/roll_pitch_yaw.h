// Fixed-axis roll, pitch, yaw: how URDF (`<origin rpy>`) and Universal Robots' kinematics files
// write a rotation.
//
//   R = Rz(yaw) Ry(pitch) Rx(roll)      (roll about the parent's x, then pitch about its y, then
//                                        yaw about its z; angles in rad)
//
// RollPitchYaw(R) is exact to rounding everywhere, gimbal lock (pitch = +-pi/2) included: it takes
// yaw from R's first column, removes it, and reads pitch and roll from entries of size one, never
// from a small cosine, so RotationFromRollPitchYaw(RollPitchYaw(R)) equals R to ~1e-15.
#pragma once

#include <Eigen/Core>

namespace cellmetry {

struct RollPitchYawAngles {
  double roll = 0.0;   // rad, about x
  double pitch = 0.0;  // rad, about y, in [-pi/2, pi/2]
  double yaw = 0.0;    // rad, about z
};

RollPitchYawAngles RollPitchYaw(const Eigen::Matrix3d& R);
Eigen::Matrix3d RotationFromRollPitchYaw(const RollPitchYawAngles& angles);

}  // namespace cellmetry
