// Ellipse through sub-pixel edge points.
//
//  1. Direct least squares (Fitzgibbon, Pilu and Fisher, "Direct least square fitting of
//     ellipses", IEEE TPAMI 21(5), 1999), in the numerically stable form of Halir and Flusser
//     ("Numerically stable direct least squares fitting of ellipses", WSCG 1998), on points
//     centred and scaled to unit RMS radius: the conic minimising the algebraic distance under
//     4ac - b^2 = 1, which is always an ellipse. This is the fit the report cites (section 4.1,
//     [33] Fitzgibbon and Fisher's "Buyer's guide to conic fitting").
//  2. Two Gauss-Newton steps on the Sampson (first-order geometric) distance in the centre and
//     shape parameters (p - c)^T M (p - c) = 1: the algebraic distance weighs points by the conic's
//     gradient, the geometric one treats every edge point alike.
//  3. The centre's covariance by first-order propagation of each point's variance through that
//     least-squares solution (the sandwich (J^T J)^-1 J^T S J (J^T J)^-1), so it follows the image
//     noise and not the fit residuals, which also hold the interpolation's systematic error.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "dot_common/edge_points.h"

namespace cellmetry::dot {

struct Ellipse {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Matrix2d shape = Eigen::Matrix2d::Identity();  // (p - centre)^T shape (p - centre) = 1
  Eigen::Matrix2d centre_covariance = Eigen::Matrix2d::Identity();  // px^2
  double rms_px = 0.0;  // RMS Sampson distance of the points
  int points = 0;

  double MajorRadius() const;
  double MinorRadius() const;
};

// std::nullopt for fewer than 6 points or when no ellipse fits (degenerate points).
std::optional<Ellipse> FitEllipse(const std::vector<EdgePoint>& points);

}  // namespace cellmetry::dot
