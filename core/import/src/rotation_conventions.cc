// Rotation conventions (rotation_conventions.h): Euler sequences, roll-pitch-yaw, quaternions,
// rotation vectors and matrices, to and from a rotation matrix.
#include "cellmetry/import/rotation_conventions.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "cellmetry/basics/transform.h"

namespace cellmetry {
namespace {

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
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

Eigen::Matrix3d ToRotation(const RotationConvention& convention, const double* v,
                           std::string* problem) {
  problem->clear();
  switch (convention.kind) {
    case RotationKind::kEuler:
      return EulerToRotation(convention.euler_axes, convention.intrinsic, {v[0], v[1], v[2]});
    case RotationKind::kRollPitchYaw:
      return EulerToRotation({0, 1, 2}, /*intrinsic=*/false, {v[0], v[1], v[2]});
    case RotationKind::kRotationVector: return RotationFromRvec(v);
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

std::array<double, 9> FromRotation(const RotationConvention& convention, const Eigen::Matrix3d& R) {
  std::array<double, 9> out{};
  switch (convention.kind) {
    case RotationKind::kEuler:
    case RotationKind::kRollPitchYaw: {
      const bool rpy = convention.kind == RotationKind::kRollPitchYaw;
      const Eigen::Vector3d a =
          RotationToEuler(rpy ? std::array<int, 3>{0, 1, 2} : convention.euler_axes,
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
