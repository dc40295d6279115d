// Rigid transforms, templated on the scalar so that one expression serves double and ceres::Jet.
//
// Convention (docs/formats.md): Transform T_a_b maps coordinates in frame b into frame a:
//   p_a = T_a_b * p_b,   T_a_c = T_a_b * T_b_c.
// Rotations are stored as 3x3 matrices; files carry rotation vectors (axis * angle, rad).
#pragma once

#include <ceres/rotation.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace cellmetry {

template <typename T>
using Vector3 = Eigen::Matrix<T, 3, 1>;
template <typename T>
using Matrix3 = Eigen::Matrix<T, 3, 3>;

template <typename T>
struct Transform {
  Matrix3<T> R = Matrix3<T>::Identity();
  Vector3<T> t = Vector3<T>::Zero();

  static Transform Identity() { return Transform(); }

  Transform operator*(const Transform& other) const {
    return Transform{R * other.R, R * other.t + t};
  }
  Vector3<T> operator*(const Vector3<T>& p) const { return R * p + t; }

  Transform inverse() const {
    Transform inv;
    inv.R = R.transpose();
    inv.t = -(inv.R * t);
    return inv;
  }

  template <typename U>
  Transform<U> cast() const {
    return Transform<U>{R.template cast<U>(), t.template cast<U>()};
  }
};

using Pose = Transform<double>;

// R = exp([rvec]x). Exact and smooth at rvec = 0 for every scalar type (Ceres handles the limit).
template <typename T>
Matrix3<T> RotationFromRvec(const T* rvec) {
  Matrix3<T> R;
  ceres::AngleAxisToRotationMatrix(rvec, R.data());  // Eigen is column-major, as is Ceres' default
  return R;
}

// The rotation vector of R, with angle in [0, pi].
inline Eigen::Vector3d RvecFromRotation(const Eigen::Matrix3d& R) {
  Eigen::Vector3d rvec;
  ceres::RotationMatrixToAngleAxis(R.data(), rvec.data());
  return rvec;
}

inline Pose PoseFromRvecT(const Eigen::Vector3d& rvec, const Eigen::Vector3d& t) {
  return Pose{RotationFromRvec(rvec.data()), t};
}

// Small rotation error vector log(R_a * R_b^T): zero when R_a == R_b; in the frame both map into.
template <typename T>
Vector3<T> RotationError(const Matrix3<T>& R_a, const Matrix3<T>& R_b) {
  const Matrix3<T> dR = R_a * R_b.transpose();
  Vector3<T> err;
  ceres::RotationMatrixToAngleAxis(dR.data(), err.data());
  return err;
}

// The chordal L2 mean of rotations: the rotation nearest (Frobenius) to their sum.
Eigen::Matrix3d MeanRotation(const std::vector<Eigen::Matrix3d>& rotations);

// Projects a near-rotation onto SO(3) (nearest in the Frobenius norm, det = +1).
Eigen::Matrix3d ProjectToRotation(const Eigen::Matrix3d& M);

}  // namespace cellmetry
