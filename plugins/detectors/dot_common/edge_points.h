// Sub-pixel edge points of one dot, from the gray levels (not the binary image): the integer
// contour is only where to look.
//
//  1. Local levels: the dot's white level is the mean inside its inner part, the black level the
//     mean of a ring outside it, both shaped by the blob's moment ellipse; the image noise is their
//     pooled standard deviation. The edge is where the gray level crosses the local 50 % level
//     (black + white) / 2: for a blurred step edge that is the edge itself whatever the blur, and a
//     global threshold would move it by (threshold - 50 % level) / edge slope.
//  2. Crossings: every row through the dot is walked from the chord's middle outwards to the first
//     pixel at or below the 50 % level, and the crossing is placed by linear interpolation between
//     that pixel and the previous one; columns likewise. A row crossing is kept where the outline
//     is closer to vertical than to horizontal (|normal x| >= |normal y|, normal from the moment
//     ellipse), a column crossing elsewhere, so each part of the outline is measured across it,
//     never along it, and once.
//  3. EdgeMethod::kProfile (default) then places each crossing by the blurred-step profile fitted
//     to all samples of its transition (edge_profile.h), which has no pixel-locking error;
//     kLinear keeps the interpolated crossing.
//  4. Each crossing's variance along its row or column follows from the gray levels it used and
//     the noise (first-order propagation), for the ellipse fit's covariance.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "cellmetry/formats/image.h"
#include "dot_common/binarize.h"
#include "dot_common/blobs.h"
#include "dot_common/edge_profile.h"

namespace cellmetry::dot {

enum class EdgeMethod { kProfile, kLinear };

struct LocalLevels {
  double black = 0.0;
  double white = 0.0;
  double noise_sigma = 0.0;    // gray levels, pooled over both regions
  double edge_width_px = 0.0;  // blur across the outline (kProfile only)
  double half() const { return 0.5 * (black + white); }
  double contrast() const { return white - black; }
};

struct EdgePoint {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  // the row (1, 0) or column (0, 1) searched
  double variance_px2 = 0.0;                             // along `direction`
};

// False when the regions leave the image (a dot cut by the border) or hold too few pixels.
bool MeasureLocalLevels(const ImageView& image, const GrayTransform& transform, const Blob& blob,
                        LocalLevels* levels);

// The dot's edge points (`points` cleared first; `crossings` is scratch). Sets
// levels->edge_width_px.
void FindEdgePoints(const ImageView& image, const GrayTransform& transform, const Blob& blob,
                    EdgeMethod method, LocalLevels* levels, std::vector<Crossing>* crossings,
                    std::vector<EdgePoint>* points);

}  // namespace cellmetry::dot
