// A dot's sub-pixel edge points (edge_points.h): local levels from its moment ellipse, then 50 %
// crossings along rows and columns, placed by interpolation or by the fitted edge profile.
#include "dot_common/edge_points.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace cellmetry::dot {
namespace {

// The blob's moment ellipse as a distance: rho(p) = 1 on its outline.
struct Outline {
  Eigen::Vector2d centre;
  Eigen::Matrix2d inverse;                     // (4 moments)^-1
  double half_width = 0.0, half_height = 0.0;  // extents of rho = 1 along x and y
  double minor_radius = 0.0;

  explicit Outline(const Blob& blob) : centre(blob.centroid) {
    const Eigen::Matrix2d shape = 4.0 * blob.moments;
    inverse = shape.inverse();
    half_width = std::sqrt(shape(0, 0));
    half_height = std::sqrt(shape(1, 1));
    const double tr = shape.trace(), det = shape.determinant();
    minor_radius =
        std::sqrt(std::max(0.5 * tr - std::sqrt(std::max(0.25 * tr * tr - det, 0.0)), 1e-6));
  }
  double Rho2(double x, double y) const {
    const double dx = x - centre.x(), dy = y - centre.y();
    return inverse(0, 0) * dx * dx + 2.0 * inverse(0, 1) * dx * dy + inverse(1, 1) * dy * dy;
  }
  Eigen::Vector2d Normal(double x, double y) const {
    return inverse * Eigen::Vector2d(x - centre.x(), y - centre.y());
  }
  // Inner region and ring (in rho) that keep the blur's tails (a couple of pixels) out of both
  // levels, whatever the dot's size.
  double WhiteRho() const {
    return std::clamp(1.0 - 2.5 / minor_radius, std::min(1.5 / minor_radius, 0.6), 0.6);
  }
  double RingInner() const { return 1.0 + std::max(0.4, 2.5 / minor_radius); }
  double RingOuter() const { return RingInner() + std::max(0.4, 2.0 / minor_radius); }
};

// Variance of the linear-interpolation crossing x0 + (a - t) / (a - b) between levels a > t >= b
// one pixel apart, each with noise sigma^2.
double CrossingVariance(double a, double b, double t, double sigma2) {
  const double d = a - b;
  return sigma2 * ((t - b) * (t - b) + (a - t) * (a - t)) / (d * d * d * d);
}

}  // namespace

bool MeasureLocalLevels(const ImageView& image, const GrayTransform& transform, const Blob& blob,
                        LocalLevels* levels) {
  const Outline o(blob);
  const double outer = o.RingOuter();
  const int x0 = static_cast<int>(std::floor(o.centre.x() - outer * o.half_width));
  const int x1 = static_cast<int>(std::ceil(o.centre.x() + outer * o.half_width));
  const int y0 = static_cast<int>(std::floor(o.centre.y() - outer * o.half_height));
  const int y1 = static_cast<int>(std::ceil(o.centre.y() + outer * o.half_height));
  if (x0 < 0 || y0 < 0 || x1 >= image.width || y1 >= image.height) return false;
  const double white2 = o.WhiteRho() * o.WhiteRho();
  const double inner2 = o.RingInner() * o.RingInner(), outer2 = outer * outer;
  double sw = 0, sww = 0, sb = 0, sbb = 0;
  int nw = 0, nb = 0;
  for (int y = y0; y <= y1; ++y) {
    const std::uint8_t* row = image.data + static_cast<size_t>(y) * image.stride;
    for (int x = x0; x <= x1; ++x) {
      const double r2 = o.Rho2(x, y);
      const double v = transform.level[row[x]];
      if (r2 <= white2) {
        sw += v, sww += v * v, ++nw;
      } else if (r2 >= inner2 && r2 <= outer2) {
        sb += v, sbb += v * v, ++nb;
      }
    }
  }
  if (nw < 3 || nb < 8) return false;
  levels->white = sw / nw;
  levels->black = sb / nb;
  const double ss = (sww - sw * sw / nw) + (sbb - sb * sb / nb);
  levels->noise_sigma = std::sqrt(std::max(ss, 0.0) / (nw + nb - 2));
  return true;
}

namespace {

// Fills the crossing's transition samples: from the last pixel above the 50 % level inwards while
// below `high`, from the first one at or below it outwards while above `low` (normalised levels),
// so that only this edge's contiguous transition is used, never a neighbouring dot's.
template <typename Level>
void CollectSamples(const Level& level, int first_inside, int steps_in, int steps_out, double black,
                    double contrast, Crossing* c) {
  constexpr double kLow = 0.02, kHigh = 0.98;
  c->count = 0;
  auto add = [&](int k) {
    const double v = (level(k) - black) / contrast;
    if (!(v > kLow && v < kHigh)) return false;
    const double u = InverseNormalCdf(v);
    c->t[c->count] = static_cast<float>(k);
    c->u[c->count] = static_cast<float>(u);
    c->w[c->count] = static_cast<float>(std::exp(-u * u));  // 2 pi phi(u)^2
    ++c->count;
    return true;
  };
  for (int k = first_inside; k > first_inside - steps_in && c->count < Crossing::kMaxSamples / 2;
       --k) {
    if (!add(k)) break;
  }
  for (int k = first_inside + 1; k <= first_inside + steps_out && c->count < Crossing::kMaxSamples;
       ++k) {
    if (!add(k)) break;
  }
}

// What every row and column through one dot shares: its outline, the local 50 % level `t`, the
// levels and noise the crossings are placed with, and how they are placed.
struct EdgeSearch {
  const Outline& outline;
  double t = 0.0, black = 0.0, contrast = 0.0, sigma2 = 0.0;
  EdgeMethod method = EdgeMethod::kProfile;
};

// The pixels a crossing of this dot may lie in, clipped to the image.
struct PixelBox {
  int xmin = 0, xmax = 0, ymin = 0, ymax = 0;
};

PixelBox SearchBox(const ImageView& image, const Outline& o) {
  const double reach = o.RingInner();  // a crossing further out than the ring is not this dot's
  PixelBox box;
  box.xmin = std::max(0, static_cast<int>(std::floor(o.centre.x() - reach * o.half_width)));
  box.xmax =
      std::min(image.width - 1, static_cast<int>(std::ceil(o.centre.x() + reach * o.half_width)));
  box.ymin = std::max(0, static_cast<int>(std::floor(o.centre.y() - reach * o.half_height)));
  box.ymax =
      std::min(image.height - 1, static_cast<int>(std::ceil(o.centre.y() + reach * o.half_height)));
  return box;
}

// One line (a row or a column) through the dot: walk from `start` both ways to the 50 % level.
// `at(i)` reads position i along the line, [lo, hi] bounds it, `other` is the fixed coordinate.
template <typename At>
void WalkLine(const EdgeSearch& s, const At& at, int start, int lo, int hi, double other,
              bool is_row, std::vector<Crossing>* crossings) {
  const double t = s.t;
  if (start < lo || start > hi || at(start) <= t) return;
  for (int step : {-1, 1}) {
    int i = start;
    while (i + step >= lo && i + step <= hi && at(i + step) > t) i += step;
    if (i + step < lo || i + step > hi) continue;  // never crossed: not an enclosed dot here
    const double a = at(i), b = at(i + step);
    const double along = i + step * (a - t) / (a - b);
    const Eigen::Vector2d p =
        is_row ? Eigen::Vector2d(along, other) : Eigen::Vector2d(other, along);
    const Eigen::Vector2d n = s.outline.Normal(p.x(), p.y());
    // Measured across the outline only: rows where it is nearer vertical, columns elsewhere.
    if (is_row ? std::abs(n.x()) < std::abs(n.y()) : std::abs(n.y()) <= std::abs(n.x())) continue;
    Crossing c;
    c.outward = (is_row ? Eigen::Vector2d::UnitX() : Eigen::Vector2d::UnitY()) * step;
    c.origin = is_row ? Eigen::Vector2d(i, other) : Eigen::Vector2d(other, i);
    c.stretch = n.norm() / std::abs(is_row ? n.x() : n.y());
    c.linear_t = (a - t) / (a - b);
    c.linear_variance = CrossingVariance(a, b, t, s.sigma2);
    if (s.method == EdgeMethod::kProfile) {
      // Outward sample k is at i + step k along the line.
      const auto outward = [&](int k) { return static_cast<double>(at(i + step * k)); };
      const int room_in = step > 0 ? i - lo : hi - i;
      const int room_out = step > 0 ? hi - i : i - lo;
      CollectSamples(outward, 0, std::min(room_in + 1, 4), std::min(room_out, 4), s.black,
                     s.contrast, &c);
    }
    crossings->push_back(c);
  }
}

// Rows: walk from the chord's middle (the ellipse's chords at height y are centred on the line
// x = cx + m_xy / m_yy (y - cy)).
void WalkRows(const ImageView& image, const GrayTransform& transform, const EdgeSearch& s,
              const Eigen::Matrix2d& m, const PixelBox& box, std::vector<Crossing>* crossings) {
  const Outline& o = s.outline;
  const auto& L = transform.level;
  const size_t stride = static_cast<size_t>(image.stride);
  for (int y = static_cast<int>(std::ceil(o.centre.y() - o.half_height));
       y <= static_cast<int>(std::floor(o.centre.y() + o.half_height)); ++y) {
    if (y < 0 || y >= image.height) continue;
    const std::uint8_t* row = image.data + static_cast<size_t>(y) * stride;
    const int start =
        static_cast<int>(std::lround(o.centre.x() + m(0, 1) / m(1, 1) * (y - o.centre.y())));
    WalkLine(
        s, [&](int x) { return L[row[x]]; }, start, box.xmin, box.xmax, y, true, crossings);
  }
}

// Columns, the same way (chords at x centred on y = cy + m_xy / m_xx (x - cx)).
void WalkColumns(const ImageView& image, const GrayTransform& transform, const EdgeSearch& s,
                 const Eigen::Matrix2d& m, const PixelBox& box, std::vector<Crossing>* crossings) {
  const Outline& o = s.outline;
  const auto& L = transform.level;
  const size_t stride = static_cast<size_t>(image.stride);
  for (int x = static_cast<int>(std::ceil(o.centre.x() - o.half_width));
       x <= static_cast<int>(std::floor(o.centre.x() + o.half_width)); ++x) {
    if (x < 0 || x >= image.width) continue;
    const std::uint8_t* column = image.data + x;
    const int start =
        static_cast<int>(std::lround(o.centre.y() + m(0, 1) / m(0, 0) * (x - o.centre.x())));
    WalkLine(
        s, [&](int y) { return L[column[y * stride]]; }, start, box.ymin, box.ymax, x, false,
        crossings);
  }
}

// Each crossing's edge point: with kProfile, placed by the blurred-step profile whose width is
// fitted over all the dot's crossings (sets levels->edge_width_px); else the interpolated one.
void PlaceEdgePoints(const std::vector<Crossing>& crossings, const EdgeSearch& s,
                     LocalLevels* levels, std::vector<EdgePoint>* points) {
  levels->edge_width_px = s.method == EdgeMethod::kProfile ? FitEdgeWidth(crossings, 0.7) : 0.0;
  const double sigma = std::sqrt(s.sigma2);
  for (const Crossing& c : crossings) {
    double along = c.linear_t, variance = c.linear_variance;
    if (s.method == EdgeMethod::kProfile && c.count > 0) {
      RefineCrossing(c, levels->edge_width_px, sigma, s.contrast, &along, &variance);
    }
    points->push_back({c.origin + along * c.outward, c.outward.cwiseAbs(), variance});
  }
}

}  // namespace

void FindEdgePoints(const ImageView& image, const GrayTransform& transform, const Blob& blob,
                    EdgeMethod method, LocalLevels* levels, std::vector<Crossing>* crossings,
                    std::vector<EdgePoint>* points) {
  points->clear();
  crossings->clear();
  const Outline o(blob);
  // A noiseless image still has quantisation noise (1/12 gray level^2).
  const double sigma2 = std::max(levels->noise_sigma * levels->noise_sigma, 1.0 / 12.0);
  const EdgeSearch search{o, levels->half(), levels->black, levels->contrast(), sigma2, method};
  const PixelBox box = SearchBox(image, o);
  WalkRows(image, transform, search, blob.moments, box, crossings);
  WalkColumns(image, transform, search, blob.moments, box, crossings);
  PlaceEdgePoints(*crossings, search, levels, points);
}

}  // namespace cellmetry::dot
