// Corner refinement by edge lines (edge_lines.h): area-method edge points across each side, a
// robust line through them, corners where lines meet, passes repeated until they settle.
#include "edge_lines.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "cellmetry/basics/statistics.h"

namespace cellmetry::fiducial {
namespace {

constexpr double kPlateau = 1.0;       // px (across the edge) averaged for a plateau level
constexpr double kFirstReach = 2.0;    // px: a blurred edge's reach assumed before it is measured
constexpr double kReach = 2.5;         // ramp widths (sigma) to where an edge has faded out
constexpr double kClean = 0.1;         // px an edge may move when its scans are cut short
constexpr double kMaxBand = 4.0;       // px: wider adds noise, not accuracy
constexpr double kMinBand = 1.5;       // px: narrower cannot hold a ramp and its plateaus
constexpr double kMinContrast = 15.0;  // gray levels between the plateaus
constexpr double kMinOutlier = 0.1;    // px off a side's line: never an outlier below this
constexpr int kMaxSamples = 64;
constexpr int kMinPoints = 6;
constexpr int kMaxPasses = 1;        // after the first, which measures the blur
constexpr int kRowStride = 3;        // pixel rows (or columns) between scans
constexpr double kConverged = 0.02;  // px: corners moved less than this, stop

struct Line {
  Eigen::Vector2d point;
  Eigen::Vector2d direction;  // unit
};

// Total least squares through `points`: the scatter's major axis, in closed form (a 2 x 2
// eigen-solver costs more than the rest of the fit).
Line Fit(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  double xx = 0.0, xy = 0.0, yy = 0.0;
  for (const auto& p : points) {
    const Eigen::Vector2d d = p - mean;
    xx += d.x() * d.x(), xy += d.x() * d.y(), yy += d.y() * d.y();
  }
  const double angle = 0.5 * std::atan2(2.0 * xy, xx - yy);
  return {mean, Eigen::Vector2d(std::cos(angle), std::sin(angle))};
}

// Samples v[k] at scan positions i0 + k, joined linearly. Positions are relative to i0 and
// non-negative, so truncation is floor.
struct Scan {
  const double* v;
  int i0;
  int n;
  double At(double x) const {
    const double f = x - i0;
    const int k = std::min(static_cast<int>(f), n - 2);
    const double t = f - k;
    return v[k] + t * (v[k + 1] - v[k]);
  }
  // Integral over [lo, hi] within the samples (trapezoids, exact for the linear join).
  double Integral(double lo, double hi) const {
    const double flo = lo - i0, fhi = hi - i0;
    const int k0 = static_cast<int>(flo) + 1, k1 = static_cast<int>(fhi);  // whole samples inside
    if (k0 > k1) return 0.5 * (At(lo) + At(hi)) * (hi - lo);
    double sum = 0.5 * (At(lo) + v[k0]) * (k0 - flo) + 0.5 * (v[k1] + At(hi)) * (fhi - k1);
    for (int k = k0; k < k1; ++k) sum += 0.5 * (v[k] + v[k + 1]);
    return sum;
  }
};

// The area method (edge_lines.h) over [lo, hi] inside the samples, plateau levels averaged over
// `plateau` at each end; false with too little contrast.
bool AreaEdge(const Scan& s, double lo, double hi, double plateau, double* edge) {
  const double a = (s.At(lo) + s.At(lo + 0.5 * plateau) + s.At(lo + plateau)) / 3;
  const double b = (s.At(hi) + s.At(hi - 0.5 * plateau) + s.At(hi - plateau)) / 3;
  if (std::abs(b - a) < kMinContrast) return false;
  *edge = hi - (s.Integral(lo, hi) - a * (hi - lo)) / (b - a);
  return true;
}

// The ramp's second moment about `edge`: steps of the edge's polarity (end minus start of the
// scan) weighted by their size. Branch-free with one division: noise makes the sign of small
// steps random, and a mispredicted branch per sample cost more than the sums.
double RampWidth(const Scan& s, double guess, double w, double edge) {
  const double polarity = s.At(guess + w) - s.At(guess - w) >= 0 ? 1.0 : -1.0;
  double mass = 0.0, moment = 0.0;
  for (int k = 0; k + 1 < s.n; ++k) {
    const double step = std::max(0.0, polarity * (s.v[k + 1] - s.v[k]));
    const double t = s.i0 + k + 0.5 - edge;
    mass += step, moment += step * t * t;
  }
  return mass > 0 ? std::sqrt(moment / mass) : w;
}

// One scan along a pixel row (along_x) or column, at index `line`, around `guess` (px along the
// scan), reaching w px either way: the edge crossing by the area method (edge_lines.h), the
// ramp's second moment, and how much the crossing moves when the scan is cut to 0.6 w (a clean
// edge with flat plateaus does not move it; a ramp wider than the scan, the next edge, or
// sharpening halos do). Scanning along the pixel grid reads pixels directly: the trapezoid rule
// over pixel values integrates a blurred edge almost exactly whatever its sub-pixel phase, and
// it is cheap. `width` and `shift` are computed only when asked for (not null). False when the
// scan leaves the image, has too little contrast, or the edge is not well inside it.
bool ScanEdge(const ImageView& im, bool along_x, int line, double guess, double w, double plateau,
              double* edge, double* width, double* shift) {
  const int i0 = static_cast<int>(std::floor(guess - w)),
            i1 = static_cast<int>(std::ceil(guess + w));
  const int n = i1 - i0 + 1;
  if (n < 4 || n > kMaxSamples) return false;
  if (along_x ? (line < 0 || line >= im.height || i0 < 0 || i1 >= im.width)
              : (line < 0 || line >= im.width || i0 < 0 || i1 >= im.height)) {
    return false;
  }
  double v[kMaxSamples];
  for (int k = 0; k < n; ++k) v[k] = along_x ? im.at(i0 + k, line) : im.at(line, i0 + k);
  const Scan scan{v, i0, n};
  if (!AreaEdge(scan, guess - w, guess + w, plateau, edge)) return false;
  if (shift != nullptr) {
    double inner = 0.0;
    if (!AreaEdge(scan, guess - 0.6 * w, guess + 0.6 * w, plateau, &inner)) return false;
    *shift = inner - *edge;
  }
  if (width != nullptr) *width = RampWidth(scan, guess, w, *edge);
  return std::abs(*edge - guess) < w - plateau;
}

// Scratch for SideLine, kept per thread so that the hot path allocates nothing.
struct SideScratch {
  std::vector<Eigen::Vector2d> points, kept;
  std::vector<double> widths, shifts, residual, sorted;
};

// `line` once more without the points far off it (a speck of dirt, a neighbour's edge): beyond 3
// robust sigmas (1.4826 median absolute residual) and kMinOutlier. When no residual exceeds
// kMinOutlier nothing can go, and the median (the costliest step of a side) is skipped.
bool Refit(SideScratch* x, Line* line) {
  const Eigen::Vector2d n(-line->direction.y(), line->direction.x());
  x->residual.clear();
  double largest = 0.0;
  for (const auto& p : x->points) {
    x->residual.push_back(std::abs((p - line->point).dot(n)));
    largest = std::max(largest, x->residual.back());
  }
  if (largest <= kMinOutlier) return true;
  x->sorted = x->residual;
  const double limit = std::max(kMinOutlier, 3.0 * 1.4826 * UpperMedian(&x->sorted));
  x->kept.clear();
  for (size_t i = 0; i < x->points.size(); ++i) {
    if (x->residual[i] <= limit) x->kept.push_back(x->points[i]);
  }
  if (static_cast<int>(x->kept.size()) < kMinPoints) return false;
  if (x->kept.size() < x->points.size()) *line = Fit(x->kept);
  return true;
}

// Edge points on the side p0 -> p1 (its first `skip0` and last `skip1` px left out), one per
// kRowStride pixel rows or columns it crosses, scanning along whichever pixel axis is nearer its
// normal, so that the scan spans `band` px either side of the edge. The line through them and,
// when asked for (not null), their median ramp width (sigma) and median shift when the scans are
// cut short (ScanEdge), across the edge.
bool SideLine(const ImageView& im, const Eigen::Vector2d& p0, const Eigen::Vector2d& p1,
              double band, double skip0, double skip1, Line* line, double* sigma, double* shift) {
  thread_local SideScratch scratch;
  SideScratch& x = scratch;
  x.points.clear(), x.widths.clear(), x.shifts.clear();
  const double length = (p1 - p0).norm();
  const Eigen::Vector2d d = (p1 - p0) / length, normal(-d.y(), d.x());
  const bool along_x = std::abs(normal.x()) >= std::abs(normal.y());
  const double cos = std::abs(along_x ? normal.x() : normal.y());  // scan axis vs normal
  const int across = along_x ? 1 : 0;                              // the coordinate of a line
  const double c0 = (p0 + skip0 * d)[across], c1 = (p0 + (length - skip1) * d)[across];
  const double slope = d[1 - across] / d[across];  // along-scan change per line
  for (int c = static_cast<int>(std::ceil(std::min(c0, c1)));
       c <= static_cast<int>(std::floor(std::max(c0, c1))); c += kRowStride) {
    const double guess = p0[1 - across] + (c - p0[across]) * slope;
    double edge = 0.0, width = 0.0, cut_shift = 0.0;
    if (!ScanEdge(im, along_x, c, guess, band / cos, kPlateau / cos, &edge,
                  sigma ? &width : nullptr, shift ? &cut_shift : nullptr)) {
      continue;
    }
    x.points.push_back(along_x ? Eigen::Vector2d(edge, c) : Eigen::Vector2d(c, edge));
    x.widths.push_back(width * cos);
    x.shifts.push_back(cut_shift * cos);
  }
  if (static_cast<int>(x.points.size()) < kMinPoints) return false;
  if (sigma != nullptr) *sigma = UpperMedian(&x.widths);
  if (shift != nullptr) *shift = UpperMedian(&x.shifts);
  *line = Fit(x.points);
  return Refit(&x, line);
}

bool Intersect(const Line& a, const Line& b, Eigen::Vector2d* point) {
  Eigen::Matrix2d m;
  m << a.direction, -b.direction;
  if (std::abs(m.determinant()) < 1e-6) return false;
  const Eigen::Vector2d ts = m.inverse() * (b.point - a.point);
  *point = a.point + ts.x() * a.direction;
  return true;
}

// Distance from side i's line to the opposite side's ends, over `cells`: a bit cell measured
// across side i (perspective makes it differ from side to side).
double CellAcross(const Quad& q, int i, int cells) {
  const Eigen::Vector2d& p0 = q[i];
  const Eigen::Vector2d& p1 = q[(i + 1) % 4];
  const Eigen::Vector2d d = (p1 - p0).normalized(), normal(-d.y(), d.x());
  const double h = std::min(std::abs((q[(i + 2) % 4] - p0).dot(normal)),
                            std::abs((q[(i + 3) % 4] - p0).dot(normal)));
  return h / cells;
}

// One fit of the four sides from the corners `in`. `reach`: how far a blurred edge reaches
// (px); each side's band stays that far short of the next edge inside (or outside) the border
// cell. When asked for (not null), *sigma: the widest side's median ramp width; *shift: the
// largest side's median shift of the edge when the scans are cut short (ScanEdge).
EdgeRefinement OnePass(const ImageView& im, int cells, double clear_cells, double reach,
                       const Quad& in, Quad* out, double* sigma, double* shift) {
  std::array<Line, 4> lines;
  if (sigma != nullptr) *sigma = 0.0;
  if (shift != nullptr) *shift = 0.0;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d& p0 = in[i];
    const Eigen::Vector2d& p1 = in[(i + 1) % 4];
    const double band = std::min(kMaxBand, clear_cells * CellAcross(in, i, cells) - reach);
    if (band < std::max(kMinBand, reach)) return EdgeRefinement::kTooSmall;  // no room for a ramp
    // Near a corner the neighbouring side enters the scan: skip until it is `reach` away. A scan
    // runs along the pixel axis nearer the side's normal, band / cos either side of the edge.
    const Eigen::Vector2d d = (p1 - p0).normalized();
    const Eigen::Vector2d axis =
        std::abs(d.y()) >= std::abs(d.x()) ? Eigen::Vector2d::UnitX() : Eigen::Vector2d::UnitY();
    const double extent = band / std::abs(axis.dot(Eigen::Vector2d(-d.y(), d.x())));
    auto skip = [&](const Eigen::Vector2d& corner, const Eigen::Vector2d& neighbour) {
      const Eigen::Vector2d b = (neighbour - corner).normalized();
      const double sin = std::abs(d.x() * b.y() - d.y() * b.x());
      const double axis_sin = std::abs(axis.x() * b.y() - axis.y() * b.x());
      return (reach + extent * axis_sin) / std::max(sin, 0.3);
    };
    const double skip0 = skip(p0, in[(i + 3) % 4]);
    const double skip1 = skip(p1, in[(i + 2) % 4]);
    double side_sigma = 0.0, side_shift = 0.0;
    if (!SideLine(im, p0, p1, band, skip0, skip1, &lines[i], sigma ? &side_sigma : nullptr,
                  shift ? &side_shift : nullptr)) {
      return EdgeRefinement::kFailed;
    }
    if (sigma != nullptr) *sigma = std::max(*sigma, side_sigma);
    if (shift != nullptr) *shift = std::max(*shift, std::abs(side_shift));
  }
  for (int i = 0; i < 4; ++i) {
    if (!Intersect(lines[(i + 3) % 4], lines[i], &(*out)[i])) return EdgeRefinement::kFailed;
  }
  return EdgeRefinement::kRefined;
}

}  // namespace

EdgeRefinement RefineByEdgeLines(const ImageView& image, int cells, double clear_cells,
                                 Quad* quad) {
  using R = EdgeRefinement;
  if (image.empty() || image.width < 2 || image.height < 2) return R::kFailed;
  // First pass with an assumed blur: it measures the blur and centres the scans on the edges.
  Quad current;
  double sigma = 0.0, shift = 0.0;
  R result = OnePass(image, cells, clear_cells, kFirstReach, *quad, &current, &sigma, nullptr);
  if (result != R::kRefined) return result;
  // Then bands that keep every other edge's ramp out of the scans, until the corners settle.
  const double reach = std::max(kFirstReach, kReach * sigma);
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    Quad next;
    result = OnePass(image, cells, clear_cells, reach, current, &next, nullptr, &shift);
    if (result != R::kRefined) return result;
    double moved = 0.0;
    for (int i = 0; i < 4; ++i) moved = std::max(moved, (next[i] - current[i]).norm());
    current = next;
    if (moved < kConverged) break;
  }
  // Edges that move when the scans are cut short are not clean steps within them (a ramp wider
  // than a cell allows, the next edge, sharpening halos): the marker is too small for its blur.
  if (shift > kClean) return R::kTooSmall;
  // A corner that moved further than a scan reaches was not found by these scans.
  for (int i = 0; i < 4; ++i) {
    if ((current[i] - (*quad)[i]).norm() > kMaxBand) return R::kFailed;
  }
  *quad = current;
  return R::kRefined;
}

}  // namespace cellmetry::fiducial
