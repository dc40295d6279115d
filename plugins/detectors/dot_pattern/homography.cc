// Plane-to-image homography (homography.h): the normalised DLT, its null vector taken as the
// eigenvector of A^T A with the smallest eigenvalue.
#include "homography.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace cellmetry::dot {
namespace {

// T with T p centred on the origin at mean distance sqrt(2).
Eigen::Matrix3d Normalising(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  double distance = 0.0;
  for (const auto& p : points) distance += (p - mean).norm();
  distance /= static_cast<double>(points.size());
  const double s = distance > 0.0 ? std::sqrt(2.0) / distance : 1.0;
  Eigen::Matrix3d t;
  t << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;
  return t;
}

}  // namespace

Eigen::Vector2d ApplyHomography(const Eigen::Matrix3d& h, const Eigen::Vector2d& p) {
  const Eigen::Vector3d q = h * p.homogeneous();
  return q.hnormalized();
}

std::optional<Eigen::Matrix3d> FitHomography(const std::vector<Eigen::Vector2d>& plane,
                                             const std::vector<Eigen::Vector2d>& image) {
  if (plane.size() < 4 || plane.size() != image.size()) return std::nullopt;
  const Eigen::Matrix3d tp = Normalising(plane), ti = Normalising(image);
  // A^T A accumulated directly (9 x 9): its eigenvector of the smallest eigenvalue is the null
  // vector of A, without forming the 2n x 9 matrix.
  Eigen::Matrix<double, 9, 9> ata = Eigen::Matrix<double, 9, 9>::Zero();
  for (size_t k = 0; k < plane.size(); ++k) {
    const Eigen::Vector3d x = tp * plane[k].homogeneous();
    const Eigen::Vector2d u = (ti * image[k].homogeneous()).head<2>();
    Eigen::Matrix<double, 9, 1> r1 = Eigen::Matrix<double, 9, 1>::Zero(), r2 = r1;
    r1.segment<3>(0) = x;
    r1.segment<3>(6) = -u.x() * x;
    r2.segment<3>(3) = x;
    r2.segment<3>(6) = -u.y() * x;
    ata += r1 * r1.transpose() + r2 * r2.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(ata);
  if (eig.info() != Eigen::Success) return std::nullopt;
  // A unique solution leaves exactly one (near) zero eigenvalue.
  if (!(eig.eigenvalues()(1) > 1e-12 * eig.eigenvalues()(8))) return std::nullopt;
  const Eigen::Matrix<double, 9, 1> v = eig.eigenvectors().col(0);
  Eigen::Matrix3d hn;
  hn << v(0), v(1), v(2), v(3), v(4), v(5), v(6), v(7), v(8);
  Eigen::Matrix3d h = ti.inverse() * hn * tp;
  if (!h.allFinite() || h(2, 2) == 0.0) return std::nullopt;
  return h / h(2, 2);
}

}  // namespace cellmetry::dot
