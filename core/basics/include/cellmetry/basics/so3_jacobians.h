// SO(3) Jacobians for analytic derivatives of rotation-vector parametrisations.
//
// With Exp(phi) the rotation of rotation vector phi (Rodrigues) and Log its inverse:
//
//   Exp(phi + d)       ~= Exp(LeftJacobian(phi) * d) * Exp(phi)            (first order in d)
//   Log(Exp(d) * R)    ~= Log(R) + InverseLeftJacobian(Log(R)) * d
//
// (Barfoot, "State Estimation for Robotics", 2017, eqs. 7.77 and 7.80; Chirikjian 2011.)
// Both are exact closed forms; near phi = 0 they switch to their Taylor series so that no
// 0/0 is ever evaluated. InverseLeftJacobian is singular at |phi| = pi, where Log itself is not
// differentiable; callers compare rotations that are close.
#pragma once

#include <Eigen/Core>

namespace cellmetry {

// [v]x, so that Skew(a) * b == a.cross(b).
inline Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return S;
}

Eigen::Matrix3d LeftJacobian(const Eigen::Vector3d& phi);
Eigen::Matrix3d InverseLeftJacobian(const Eigen::Vector3d& phi);

// phi = Log(R_a R_b^T) (RotationError, transform.h) and InverseLeftJacobian(phi) together, the
// angle's sine and cosine read off the rotation (half the antisymmetric part's norm, and
// (trace - 1) / 2) instead of computed again: one atan2 and no sine or cosine. A rotation
// residual's linearization runs this once per comparison, 11,250 times per pass on exp_a.
// Beyond 2.5 rad, where the sine read off the matrix loses digits, the separate functions.
void RotationErrorAndInverseJacobian(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b,
                                     Eigen::Vector3d* phi, Eigen::Matrix3d* inverse_jacobian);

}  // namespace cellmetry
