// SO(3) left Jacobian and its inverse (so3_jacobians.h): the closed forms, switching to their
// Taylor series at small angles where the closed forms lose digits to cancellation.
#include "cellmetry/basics/so3_jacobians.h"

#include <cmath>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

// Below this angle the closed forms lose digits to cancellation; the series (to theta^4) are
// exact to double precision there.
constexpr double kSeriesAngle = 1e-4;

Eigen::Matrix3d LeftJacobian(const Eigen::Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const double theta = std::sqrt(theta2);
  double a, b;  // J = I + a [phi]x + b [phi]x^2
  if (theta < kSeriesAngle) {
    a = 0.5 - theta2 / 24.0;
    b = 1.0 / 6.0 - theta2 / 120.0;
  } else {
    a = (1.0 - std::cos(theta)) / theta2;
    b = (theta - std::sin(theta)) / (theta2 * theta);
  }
  const Eigen::Matrix3d S = Skew(phi);
  return Eigen::Matrix3d::Identity() + a * S + b * S * S;
}

Eigen::Matrix3d InverseLeftJacobian(const Eigen::Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const double theta = std::sqrt(theta2);
  double c;  // J^-1 = I - 1/2 [phi]x + c [phi]x^2
  if (theta < kSeriesAngle) {
    c = 1.0 / 12.0 + theta2 / 720.0;
  } else {
    c = 1.0 / theta2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
  }
  const Eigen::Matrix3d S = Skew(phi);
  return Eigen::Matrix3d::Identity() - 0.5 * S + c * S * S;
}

void RotationErrorAndInverseJacobian(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b,
                                     Eigen::Vector3d* phi, Eigen::Matrix3d* inverse_jacobian) {
  const Eigen::Matrix3d E = R_a * R_b.transpose();
  const double cos_theta = 0.5 * (E.trace() - 1.0);
  if (cos_theta < std::cos(2.5)) {  // near pi: the separate, quaternion-based forms
    *phi = RotationError<double>(R_a, R_b);
    *inverse_jacobian = InverseLeftJacobian(*phi);
    return;
  }
  // E = I + sin(theta) [n]x + (1 - cos(theta)) [n]x^2: its antisymmetric part is sin(theta) [n]x.
  const Eigen::Vector3d sin_axis(0.5 * (E(2, 1) - E(1, 2)), 0.5 * (E(0, 2) - E(2, 0)),
                                 0.5 * (E(1, 0) - E(0, 1)));
  const double sin_theta = sin_axis.norm();
  const double theta = std::atan2(sin_theta, cos_theta);
  const double theta2 = theta * theta;
  double k;  // J^-1 = I - 1/2 [phi]x + k [phi]x^2, as InverseLeftJacobian
  if (theta < kSeriesAngle) {
    *phi = (1.0 + theta2 / 6.0) * sin_axis;  // theta / sin(theta)
    k = 1.0 / 12.0 + theta2 / 720.0;
  } else {
    *phi = (theta / sin_theta) * sin_axis;
    k = 1.0 / theta2 - (1.0 + cos_theta) / (2.0 * theta * sin_theta);
  }
  const Eigen::Matrix3d S = Skew(*phi);
  *inverse_jacobian = Eigen::Matrix3d::Identity() - 0.5 * S + k * S * S;
}

}  // namespace cellmetry
