// Ellipse fit (ellipse_fit.h): Halir-Flusser direct least squares on normalised points,
// Gauss-Newton on the Sampson distance, the centre's covariance by first-order propagation.
#include "dot_common/ellipse_fit.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace cellmetry::dot {
namespace {

using Vector5d = Eigen::Matrix<double, 5, 1>;
using Matrix5d = Eigen::Matrix<double, 5, 5>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// Halir-Flusser's reduced eigenproblem for the conic a x^2 + b xy + c y^2 + d x + e y + f = 0.
std::optional<Vector6d> DirectFit(const std::vector<Eigen::Vector2d>& q) {
  Eigen::Matrix3d s1 = Eigen::Matrix3d::Zero(), s2 = Eigen::Matrix3d::Zero(),
                  s3 = Eigen::Matrix3d::Zero();
  for (const auto& p : q) {
    const Eigen::Vector3d quadratic(p.x() * p.x(), p.x() * p.y(), p.y() * p.y());
    const Eigen::Vector3d linear(p.x(), p.y(), 1.0);
    s1 += quadratic * quadratic.transpose();
    s2 += quadratic * linear.transpose();
    s3 += linear * linear.transpose();
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> s3_lu(s3);
  if (!s3_lu.isInvertible()) return std::nullopt;
  const Eigen::Matrix3d t = -s3_lu.solve(s2.transpose());
  const Eigen::Matrix3d reduced = s1 + s2 * t;
  // Premultiply by the inverse of the constraint matrix [[0, 0, 2], [0, -1, 0], [2, 0, 0]].
  Eigen::Matrix3d m;
  m.row(0) = reduced.row(2) / 2.0;
  m.row(1) = -reduced.row(1);
  m.row(2) = reduced.row(0) / 2.0;
  const Eigen::EigenSolver<Eigen::Matrix3d> eig(m);
  if (eig.info() != Eigen::Success) return std::nullopt;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d a1 = eig.eigenvectors().col(i).real();
    if (4.0 * a1(0) * a1(2) - a1(1) * a1(1) > 0.0) {  // the one elliptic solution
      Vector6d conic;
      conic << a1, t * a1;
      return conic;
    }
  }
  return std::nullopt;
}

// Conic -> centre and shape (p - c)^T M (p - c) = 1; nullopt unless a real ellipse.
bool ToCentreShape(const Vector6d& k, Eigen::Vector2d* c, Eigen::Matrix2d* shape) {
  Eigen::Matrix2d quad;
  quad << k(0), k(1) / 2, k(1) / 2, k(2);
  const double det = quad.determinant();
  if (!(det > 0.0)) return false;
  *c = -0.5 * quad.inverse() * Eigen::Vector2d(k(3), k(4));
  const double at_centre = k(5) + 0.5 * (k(3) * c->x() + k(4) * c->y());
  if (at_centre == 0.0) return false;
  *shape = -quad / at_centre;
  return shape->trace() > 0.0 && shape->determinant() > 0.0;
}

struct Normal {  // J^T J and J^T r of the Sampson residuals, and the sandwich's middle
  Matrix5d jtj = Matrix5d::Zero();
  Vector5d jtr = Vector5d::Zero();
  Matrix5d jsj = Matrix5d::Zero();
  double rr = 0.0;
};

Normal Linearise(const std::vector<EdgePoint>& points, const Eigen::Vector2d& c,
                 const Eigen::Matrix2d& shape) {
  Normal n;
  for (const auto& point : points) {
    const Eigen::Vector2d q = point.pixel - c;
    const Eigen::Vector2d mq = shape * q;
    const double g = 2.0 * mq.norm();  // |grad f|, f = q^T M q - 1
    const double r = (q.dot(mq) - 1.0) / g;
    Vector5d j;
    j << -2.0 * mq / g, q.x() * q.x() / g, 2.0 * q.x() * q.y() / g, q.y() * q.y() / g;
    n.jtj += j * j.transpose();
    n.jtr += j * r;
    n.rr += r * r;
    // The point's displacement along its search direction moves it along the normal by n . dir.
    const double along = (2.0 * mq / g).dot(point.direction);
    n.jsj += (point.variance_px2 * along * along) * j * j.transpose();
  }
  return n;
}

}  // namespace

double Ellipse::MajorRadius() const {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> e(shape);
  return 1.0 / std::sqrt(e.eigenvalues()(0));
}

double Ellipse::MinorRadius() const {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> e(shape);
  return 1.0 / std::sqrt(e.eigenvalues()(1));
}

std::optional<Ellipse> FitEllipse(const std::vector<EdgePoint>& points) {
  const int n = static_cast<int>(points.size());
  if (n < 6) return std::nullopt;
  // Centre and scale the points (Hartley-style normalisation) for the direct fit.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p.pixel;
  mean /= n;
  double spread = 0.0;
  for (const auto& p : points) spread += (p.pixel - mean).squaredNorm();
  const double scale = std::sqrt(spread / n);
  if (!(scale > 0.0)) return std::nullopt;
  // Everything below runs on the normalised points (their variances scaled alike), which keeps
  // the centre and shape parameters of comparable size in the normal equations.
  std::vector<EdgePoint> normalised(points);
  std::vector<Eigen::Vector2d> xy(n);
  for (int i = 0; i < n; ++i) {
    normalised[i].pixel = (points[i].pixel - mean) / scale;
    normalised[i].variance_px2 = points[i].variance_px2 / (scale * scale);
    xy[i] = normalised[i].pixel;
  }
  const std::optional<Vector6d> conic = DirectFit(xy);
  if (!conic) return std::nullopt;
  Ellipse e;
  if (!ToCentreShape(*conic, &e.centre, &e.shape)) return std::nullopt;

  Normal normal;
  for (int iteration = 0; iteration < 3; ++iteration) {
    normal = Linearise(normalised, e.centre, e.shape);
    if (iteration == 2) break;
    const Vector5d step = normal.jtj.ldlt().solve(-normal.jtr);
    if (!step.allFinite()) return std::nullopt;
    Eigen::Vector2d centre = e.centre + step.head<2>();
    Eigen::Matrix2d shape;
    shape << e.shape(0, 0) + step(2), e.shape(0, 1) + step(3), e.shape(0, 1) + step(3),
        e.shape(1, 1) + step(4);
    if (!(shape.determinant() > 0.0 && shape.trace() > 0.0)) break;  // keep the direct fit
    e.centre = centre;
    e.shape = shape;
  }
  const Eigen::LDLT<Matrix5d> jtj(normal.jtj);
  const Matrix5d inverse = jtj.solve(Matrix5d::Identity());
  e.centre_covariance = (inverse * normal.jsj * inverse).topLeftCorner<2, 2>() * (scale * scale);
  e.rms_px = std::sqrt(normal.rr / std::max(n - 5, 1)) * scale;
  e.points = n;
  e.centre = mean + scale * e.centre;
  e.shape /= scale * scale;
  if (!e.centre.allFinite() || !e.centre_covariance.allFinite()) return std::nullopt;
  return e;
}

}  // namespace cellmetry::dot
