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

}  // namespace cellmetry
