// Euler angles (euler_angles.h): the 12 sequences, intrinsic and extrinsic, to and from a
// rotation matrix.
#include "cellmetry/basics/euler_angles.h"

#include <Eigen/Geometry>
#include <cmath>

namespace cellmetry {
namespace {

// +1 when axis j follows axis i cyclically (x->y, y->z, z->x), -1 otherwise: the sign of
// e_i x e_j along the third axis.
int Parity(int i, int j) { return j == (i + 1) % 3 ? 1 : -1; }

// Below this, the middle angle sits at gimbal lock: the first and last axes coincide and only
// their sum (or difference) is defined; the last angle is then taken as zero.
constexpr double kGimbalLock = 1e-10;

// Intrinsic R = R_i(a) R_j(b) R_k(c): the angles (a, b, c).
Eigen::Vector3d IntrinsicAngles(const std::array<int, 3>& axes, const Eigen::Matrix3d& R) {
  const int i = axes[0], j = axes[1];
  if (axes[2] != i) {  // Tait-Bryan: three different axes
    const int k = axes[2];
    const double s = Parity(i, j);
    const double cos_b = std::hypot(R(i, i), R(i, j));
    const double b = std::atan2(s * R(i, k), cos_b);
    if (cos_b < kGimbalLock) return {std::atan2(s * R(k, j), R(j, j)), b, 0.0};
    return {std::atan2(-s * R(j, k), R(k, k)), b, std::atan2(-s * R(i, j), R(i, i))};
  }
  // Proper Euler: first and last axis the same; k the axis not named.
  const int k = 3 - i - j;
  const double s = Parity(i, j);
  const double sin_b = std::hypot(R(i, j), R(i, k));
  const double b = std::atan2(sin_b, R(i, i));
  if (sin_b < kGimbalLock) return {std::atan2(s * R(k, j), R(j, j)), b, 0.0};
  return {std::atan2(R(j, i), -s * R(k, i)), b, std::atan2(R(i, j), s * R(i, k))};
}

}  // namespace

std::optional<std::array<int, 3>> ParseEulerOrder(const std::string& order) {
  if (order.size() != 3) return std::nullopt;
  std::array<int, 3> axes{};
  for (int n = 0; n < 3; ++n) {
    const char c = order[n];
    if (c < 'X' || c > 'Z') return std::nullopt;
    axes[n] = c - 'X';
  }
  if (axes[0] == axes[1] || axes[1] == axes[2]) return std::nullopt;
  return axes;
}

Eigen::Matrix3d AxisRotation(int axis, double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
}

Eigen::Matrix3d EulerToRotation(const std::array<int, 3>& axes, bool intrinsic,
                                const Eigen::Vector3d& angles_rad) {
  const Eigen::Matrix3d R1 = AxisRotation(axes[0], angles_rad[0]);
  const Eigen::Matrix3d R2 = AxisRotation(axes[1], angles_rad[1]);
  const Eigen::Matrix3d R3 = AxisRotation(axes[2], angles_rad[2]);
  return intrinsic ? Eigen::Matrix3d(R1 * R2 * R3) : Eigen::Matrix3d(R3 * R2 * R1);
}

Eigen::Vector3d RotationToEuler(const std::array<int, 3>& axes, bool intrinsic,
                                const Eigen::Matrix3d& R) {
  if (intrinsic) return IntrinsicAngles(axes, R);
  // Fixed axes (i, j, k) turned by (a, b, c) are turned axes (k, j, i) turned by (c, b, a).
  const Eigen::Vector3d reversed = IntrinsicAngles({axes[2], axes[1], axes[0]}, R);
  return {reversed[2], reversed[1], reversed[0]};
}

}  // namespace cellmetry
