// Fixed-axis roll, pitch, yaw from a rotation and back (roll_pitch_yaw.h).
//
// With R = Rz(y) M and M = Ry(p) Rx(r) = [[cp, sp sr, sp cr], [0, cr, -sr], [-sp, cp sr, cp cr]]:
// y = atan2(R10, R00) makes M's entry (1,0) zero (any y will do when the first column is along z:
// gimbal lock); then p = atan2(-M20, M00) and r = atan2(-M12, M11) read entries that are never
// both small, so no angle is taken from a ratio of two tiny numbers.
#include "cellmetry/exports/roll_pitch_yaw.h"

#include <Eigen/Geometry>
#include <cmath>

namespace cellmetry {

RollPitchYawAngles RollPitchYaw(const Eigen::Matrix3d& R) {
  RollPitchYawAngles a;
  a.yaw = std::atan2(R(1, 0), R(0, 0));
  const Eigen::Matrix3d M =
      Eigen::AngleAxisd(-a.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R;
  a.pitch = std::atan2(-M(2, 0), M(0, 0));
  a.roll = std::atan2(-M(1, 2), M(1, 1));
  return a;
}

Eigen::Matrix3d RotationFromRollPitchYaw(const RollPitchYawAngles& a) {
  return (Eigen::AngleAxisd(a.yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(a.pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(a.roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace cellmetry
