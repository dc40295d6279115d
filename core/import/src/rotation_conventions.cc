// Rotation conventions (rotation_conventions.h): Euler sequences, roll-pitch-yaw, quaternions,
// rotation vectors and matrices, to and from a rotation matrix.
#include "cellmetry/import/rotation_conventions.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "cellmetry/basics/transform.h"

namespace cellmetry {
namespace {

// +1 when axis j follows axis i cyclically (x->y, y->z, z->x), -1 otherwise: the sign of
// e_i x e_j along the third axis.
int Parity(int i, int j) { return j == (i + 1) % 3 ? 1 : -1; }

// Below this, the middle angle sits at gimbal lock: the first and last axes coincide and only
// their sum (or difference) is defined; the last angle is then taken as zero.
constexpr double kGimbalLock = 1e-10;

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

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

int RotationConvention::value_count() const {
  switch (kind) {
    case RotationKind::kQuaternion: return 4;
    case RotationKind::kMatrix: return 9;
    default: return 3;
  }
}

bool RotationConvention::values_are_angles() const {
  return kind == RotationKind::kEuler || kind == RotationKind::kRollPitchYaw ||
         kind == RotationKind::kRotationVector;
}

std::string RotationConvention::Describe() const {
  switch (kind) {
    case RotationKind::kEuler: {
      std::string order;
      for (int axis : euler_axes) order += static_cast<char>('X' + axis);
      return "euler " + order + (intrinsic ? " intrinsic" : " extrinsic");
    }
    case RotationKind::kRollPitchYaw: return "rpy";
    case RotationKind::kQuaternion: return scalar_first ? "quaternion wxyz" : "quaternion xyzw";
    case RotationKind::kRotationVector: return "rotation_vector";
    case RotationKind::kMatrix: return "matrix";
  }
  return "";
}

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

Eigen::Matrix3d ToRotation(const RotationConvention& convention, const double* v,
                           std::string* problem) {
  problem->clear();
  switch (convention.kind) {
    case RotationKind::kEuler:
      return EulerToRotation(convention.euler_axes, convention.intrinsic, {v[0], v[1], v[2]});
    case RotationKind::kRollPitchYaw:
      return EulerToRotation({0, 1, 2}, /*intrinsic=*/false, {v[0], v[1], v[2]});
    case RotationKind::kRotationVector:
      return RotationFromRvec(v);
    case RotationKind::kQuaternion: {
      const Eigen::Quaterniond q = convention.scalar_first
                                       ? Eigen::Quaterniond(v[0], v[1], v[2], v[3])
                                       : Eigen::Quaterniond(v[3], v[0], v[1], v[2]);
      const double length = q.norm();
      if (!(length > 0)) {
        *problem = "the quaternion is zero";
        return Eigen::Matrix3d::Identity();
      }
      if (std::abs(length - 1.0) > convention.tolerance) {
        *problem = "the quaternion's length is " + Number(length) + ", not 1 (tolerance " +
                   Number(convention.tolerance) + ")";
      }
      return q.normalized().toRotationMatrix();
    }
    case RotationKind::kMatrix: {
      Eigen::Matrix3d M;
      M << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
      const double determinant = M.determinant();
      const double off = (M.transpose() * M - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
      if (!(determinant > 0)) {
        *problem = "the matrix's determinant is " + Number(determinant) +
                   ": a mirrored frame, not a rotation";
        return Eigen::Matrix3d::Identity();
      }
      if (off > convention.tolerance) {
        *problem = "the matrix is not orthonormal: R^T R differs from the identity by up to " +
                   Number(off) + " (tolerance " + Number(convention.tolerance) + ")";
      }
      return ProjectToRotation(M);
    }
  }
  return Eigen::Matrix3d::Identity();
}

std::array<double, 9> FromRotation(const RotationConvention& convention,
                                   const Eigen::Matrix3d& R) {
  std::array<double, 9> out{};
  switch (convention.kind) {
    case RotationKind::kEuler:
    case RotationKind::kRollPitchYaw: {
      const bool rpy = convention.kind == RotationKind::kRollPitchYaw;
      const Eigen::Vector3d a = RotationToEuler(rpy ? std::array<int, 3>{0, 1, 2}
                                                    : convention.euler_axes,
                                                rpy ? false : convention.intrinsic, R);
      out = {a[0], a[1], a[2]};
      break;
    }
    case RotationKind::kRotationVector: {
      const Eigen::Vector3d r = RvecFromRotation(R);
      out = {r[0], r[1], r[2]};
      break;
    }
    case RotationKind::kQuaternion: {
      Eigen::Quaterniond q(R);
      if (q.w() < 0) q.coeffs() = -q.coeffs();
      if (convention.scalar_first) {
        out = {q.w(), q.x(), q.y(), q.z()};
      } else {
        out = {q.x(), q.y(), q.z(), q.w()};
      }
      break;
    }
    case RotationKind::kMatrix:
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) out[3 * r + c] = R(r, c);
      }
      break;
  }
  return out;
}

}  // namespace cellmetry
