// SO(3) left Jacobian and its inverse (so3_jacobians.h): the closed forms, switching to their
// Taylor series at small angles where the closed forms lose digits to cancellation.
#include "cellmetry/basics/so3_jacobians.h"

#include <cmath>

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

}  // namespace cellmetry
