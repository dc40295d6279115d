// Sub-pixel position of one edge crossing from the gray levels across it.
//
// Linear interpolation of the 50 % crossing (edge_points.h) uses two samples of an S-shaped
// profile as if it were a straight line: its error depends on where the edge falls between the
// samples ("pixel locking"), up to 0.03 px per crossing for a 0.6 px blur, and it does not average
// out over a dot: the white dot's centre moved by up to 0.013 px with its sub-pixel position
// (tests/test_dot_detectors.cc, edge: linear).
//
// The profile model removes it. A blurred step across an edge at e is, to a very good
// approximation, black + (white - black) Phi((e - t) / s) along the outward coordinate t (Phi the
// normal CDF; s^2 = blur^2 + 1/12 for pixel integration, stretched by 1 / |n . direction| when
// the row crosses the outline obliquely). Each sample in the transition gives, through the probit
// u = Phi^-1((level - black) / (white - black)), one linear equation t = e - s u with variance
// proportional to 1 / phi(u)^2; their weighted mean is e, the maximum-likelihood position for
// that model, and it reaches the Cramer-Rao bound of the samples. s is common to the dot (one
// blur) and is fitted in closed form over all its crossings first.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace cellmetry::dot {

// The samples across one crossing, in the outward coordinate t (pixels along the search
// direction, increasing away from the dot's inside).
struct Crossing {
  static constexpr int kMaxSamples = 8;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();    // pixel at t = 0
  Eigen::Vector2d outward = Eigen::Vector2d::UnitX();  // +-x or +-y
  double stretch = 1.0;   // 1 / |outline normal . outward|: the profile's width along t
  double linear_t = 0.0;  // the 50 % crossing by linear interpolation
  double linear_variance = 0.0;
  int count = 0;
  std::array<float, kMaxSamples> t{}, u{}, w{};  // position, probit, weight exp(-u^2)
};

// Inverse of the standard normal CDF (Acklam's rational approximation, relative error 1.2e-9).
double InverseNormalCdf(double p);

// Blur width s (px, across the outline) common to all crossings; `fallback` when they do not
// determine it.
double FitEdgeWidth(const std::vector<Crossing>& crossings, double fallback);

// The crossing's edge position along t and its variance (px^2) for image noise `sigma` and
// `contrast` (gray levels), given the width across the outline.
void RefineCrossing(const Crossing& c, double width, double sigma, double contrast, double* t,
                    double* variance);

}  // namespace cellmetry::dot
