// Which found dot is which layout dot (pattern_matcher.h): the 13 nearest the median, whitened
// and turned onto the diamond, then checked by the layout -> image homography.
#include "pattern_matcher.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <sstream>

#include "cellmetry/basics/statistics.h"
#include "diamond_layout.h"
#include "homography.h"

namespace cellmetry::dot {
namespace {

std::string Where(const Eigen::Vector2d& p) {
  std::ostringstream s;
  s.precision(1);
  s << std::fixed << "(" << p.x() << ", " << p.y() << ")";
  return s.str();
}

// 1. The indices of the 13 points nearest the coordinate-wise median, nearest first.
std::vector<int> NearestMedian(const std::vector<Eigen::Vector2d>& points) {
  std::vector<double> xs, ys;
  for (const auto& p : points) xs.push_back(p.x()), ys.push_back(p.y());
  const Eigen::Vector2d median(Median(xs), Median(ys));
  std::vector<int> index(points.size());
  std::iota(index.begin(), index.end(), 0);
  std::stable_sort(index.begin(), index.end(), [&](int a, int b) {
    return (points[a] - median).squaredNorm() < (points[b] - median).squaredNorm();
  });
  index.resize(kPatternDots);
  return index;
}

// 2. The chosen points whitened by their mean and covariance, scaled to the layout's variance per
// axis; nullopt when they lie on a line.
std::optional<std::vector<Eigen::Vector2d>> Whitened(const std::vector<Eigen::Vector2d>& points,
                                                     const std::vector<int>& index) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int i : index) mean += points[i];
  mean /= kPatternDots;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (int i : index) cov += (points[i] - mean) * (points[i] - mean).transpose();
  cov /= kPatternDots;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  if (!(eig.eigenvalues()(0) > 1e-3 * eig.eigenvalues()(1))) return std::nullopt;
  const double layout_variance = 14.0 / kPatternDots;  // per axis, in pitches^2
  const Eigen::Matrix2d whiten = eig.operatorInverseSqrt() * std::sqrt(layout_variance);
  std::vector<Eigen::Vector2d> w(kPatternDots);
  for (int k = 0; k < kPatternDots; ++k) w[k] = whiten * (points[index[k]] - mean);
  return w;
}

// 2. Layout (i, j) -> whitened image: the turn by the phase of sum w^4 over the four outermost
// points (the diamond's tips), with y mirrored.
Eigen::Matrix2d DiamondTurn(const std::vector<Eigen::Vector2d>& w) {
  std::vector<int> by_radius(kPatternDots);
  std::iota(by_radius.begin(), by_radius.end(), 0);
  std::sort(by_radius.begin(), by_radius.end(),
            [&](int a, int b) { return w[a].squaredNorm() > w[b].squaredNorm(); });
  std::complex<double> sum4 = 0.0;
  for (int k = 0; k < 4; ++k)
    sum4 += std::pow(std::complex<double>(w[by_radius[k]].x(), w[by_radius[k]].y()), 4);
  const double angle = std::arg(sum4) / 4.0;  // (-45, 45] degrees: target x nearest image +x
  Eigen::Matrix2d turn;  // layout (i, j) -> whitened image: rotate, with y mirrored
  turn << std::cos(angle), std::sin(angle), std::sin(angle), -std::cos(angle);
  return turn;
}

// 3. Nearest layout position for each dot, each taken once: fills `order` (order[id] = index into
// `points`) and returns why not ("" when every dot has its id).
std::string AssignIds(const std::vector<Eigen::Vector2d>& points, const std::vector<int>& index,
                      const std::vector<Eigen::Vector2d>& w, const Eigen::Matrix2d& turn,
                      std::vector<int>* order) {
  const std::vector<Eigen::Vector2d>& grid = DiamondGrid();
  order->assign(kPatternDots, -1);
  for (int k = 0; k < kPatternDots; ++k) {
    int best = 0;
    double best_d2 = 1e300;
    for (int id = 0; id < kPatternDots; ++id) {
      const double d2 = (turn * grid[id] - w[k]).squaredNorm();
      if (d2 < best_d2) best_d2 = d2, best = id;
    }
    if (best_d2 > 0.3 * 0.3 || (*order)[best] >= 0) {
      return "ambiguous pattern: the dot at " + Where(points[index[k]]) +
             " is not where the 13-dot diamond has one";
    }
    (*order)[best] = index[k];
  }
  return "";
}

// 4. The homography must reproduce every dot: sets match->homography and max_error_px, and
// match->failure when it does not.
void CheckHomography(const std::vector<Eigen::Vector2d>& points, double pitch_mm,
                     double max_layout_error_px, PatternMatch* match) {
  const std::vector<Eigen::Vector2d>& grid = DiamondGrid();
  std::vector<Eigen::Vector2d> plane, image;
  for (int id = 0; id < kPatternDots; ++id) {
    plane.push_back(grid[id] * pitch_mm);
    image.push_back(points[match->order[id]]);
  }
  const std::optional<Eigen::Matrix3d> h = FitHomography(plane, image);
  if (!h) {
    match->failure = "ambiguous pattern: no homography maps the layout onto the dots";
    return;
  }
  match->homography = *h;
  int worst = 0;
  for (int id = 0; id < kPatternDots; ++id) {
    const double e = (ApplyHomography(*h, plane[id]) - image[id]).norm();
    if (e > match->max_error_px) match->max_error_px = e, worst = id;
  }
  if (match->max_error_px > max_layout_error_px) {
    std::ostringstream s;
    s.precision(2);
    s << std::fixed << "ambiguous pattern: dot " << worst + 1 << " at " << Where(image[worst])
      << " is " << match->max_error_px << " px from where the layout puts it (max_layout_error_px "
      << max_layout_error_px << ")";
    match->failure = s.str();
  }
}

}  // namespace

PatternMatch MatchDiamond(const std::vector<Eigen::Vector2d>& points, double pitch_mm,
                          double max_layout_error_px) {
  PatternMatch match;
  // 1. The 13 nearest the median.
  match.chosen = NearestMedian(points);
  // 2. Whiten, and find the turn that takes the layout onto the whitened dots.
  const std::optional<std::vector<Eigen::Vector2d>> w = Whitened(points, match.chosen);
  if (!w) {
    match.failure = "ambiguous pattern: the 13 dots nearest the centre lie on a line";
    return match;
  }
  const Eigen::Matrix2d turn = DiamondTurn(*w);
  // 3. Nearest layout position for each dot, each taken once.
  match.failure = AssignIds(points, match.chosen, *w, turn, &match.order);
  if (!match.failure.empty()) return match;
  // 4. The homography must reproduce every dot.
  CheckHomography(points, pitch_mm, max_layout_error_px, &match);
  return match;
}

}  // namespace cellmetry::dot
