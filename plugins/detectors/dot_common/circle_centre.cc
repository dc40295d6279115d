// Perspective eccentricity correction (circle_centre.h): the two circles of known radius whose
// image is the ellipse, from the cone's eigen-decomposition, and the one nearer a normal hint.
#include "dot_common/circle_centre.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace cellmetry::dot {

std::optional<std::array<Circle3d, 2>> CirclesFromConic(const Eigen::Matrix3d& conic,
                                                        double radius_mm) {
  Eigen::Matrix3d q = 0.5 * (conic + conic.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(q);
  if (eig.info() != Eigen::Success) return std::nullopt;
  Eigen::Vector3d l = eig.eigenvalues();  // ascending
  Eigen::Matrix3d v = eig.eigenvectors();
  // A real cone has signature (+, +, -) up to the conic's arbitrary sign.
  if (l(1) < 0.0) {
    q = -q;
    eig.compute(q);
    l = eig.eigenvalues();
    v = eig.eigenvectors();
  }
  if (!(l(0) < 0.0 && l(1) > 0.0)) return std::nullopt;
  const double l1 = l(2), l2 = l(1), l3 = l(0);
  const Eigen::Vector3d e1 = v.col(2), e2 = v.col(1), e3 = v.col(0);
  const double s1 = std::sqrt(l1 - l2), s3 = std::sqrt(l2 - l3), norm = std::sqrt(l1 - l3);
  // In the eigenframe the cone is l1 x^2 + l2 y^2 + l3 z^2 = 0 and
  //   Q - l2 I = (s1 x - sigma s3 z)(s1 x + sigma s3 z),
  // so on the plane s1 x - sigma s3 z = h the cone is the sphere l2 |X|^2 + h (s1 x + sigma s3 z) =
  // 0 (through the origin, centre -h / (2 l2) (s1, 0, sigma s3)); the circle is that sphere cut by
  // the plane. Its radius^2 works out to -h^2 l1 l3 / (l2^2 (l1 - l3)), which gives h.
  const double h = radius_mm * l2 * norm / std::sqrt(-l1 * l3);
  std::array<Circle3d, 2> out;
  for (int k = 0; k < 2; ++k) {
    const double sigma = k == 0 ? 1.0 : -1.0;
    const Eigen::Vector3d n(s1 / norm, 0.0, -sigma * s3 / norm);
    const Eigen::Vector3d sphere = -h / (2.0 * l2) * Eigen::Vector3d(s1, 0.0, sigma * s3);
    const double d = h / norm;  // the plane is n . X = d
    const Eigen::Vector3d centre = sphere + (d - n.dot(sphere)) * n;
    Circle3d c;
    c.centre_mm = centre.x() * e1 + centre.y() * e2 + centre.z() * e3;
    c.normal = n.x() * e1 + n.y() * e2 + n.z() * e3;
    if (c.centre_mm.z() < 0.0) c.centre_mm = -c.centre_mm;      // the other sign of h: in front
    if (c.normal.dot(c.centre_mm) > 0.0) c.normal = -c.normal;  // printed side toward the camera
    out[k] = c;
  }
  return out;
}

Eigen::Matrix3d NormalisedConic(const Ellipse& ellipse, const ImageGeometry& geometry) {
  // (u - c)^T M (u - c) = 1 in ideal pixels u = K x.
  const Eigen::Matrix2d& m = ellipse.shape;
  const Eigen::Vector2d mc = m * ellipse.centre;
  Eigen::Matrix3d pixel;
  pixel << m(0, 0), m(0, 1), -mc.x(), m(1, 0), m(1, 1), -mc.y(), -mc.x(), -mc.y(),
      ellipse.centre.dot(mc) - 1.0;
  const Eigen::Matrix3d k = geometry.IdealFromNormalised();
  return k.transpose() * pixel * k;
}

std::optional<Circle3d> CircleNearest(const Ellipse& ellipse, const ImageGeometry& geometry,
                                      double radius_mm, const Eigen::Vector3d& normal_hint) {
  const auto circles = CirclesFromConic(NormalisedConic(ellipse, geometry), radius_mm);
  if (!circles) return std::nullopt;
  const Eigen::Vector3d hint = normal_hint.normalized();
  return (*circles)[0].normal.dot(hint) >= (*circles)[1].normal.dot(hint) ? (*circles)[0]
                                                                          : (*circles)[1];
}

}  // namespace cellmetry::dot
