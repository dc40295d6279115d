// Which found dot is which layout dot (Porée 2023, section 4.1, figure 11b, with the report's
// rectangularity check replaced by a match to the known layout):
//
//  1. Keep the 13 dots nearest the cloud's centre (the report's filter against look-alikes in the
//     scene), the centre taken as the coordinate-wise median so that a far stray dot does not pull
//     it off the pattern.
//  2. Whiten the 13 points by their mean and covariance. An affine view of the diamond (isotropic
//     second moment) whitens to the diamond itself turned by some angle and mirrored in y (a face
//     is seen from its printed side, so target y up maps to image y down); the angle, modulo the
//     pattern's 90 degree symmetry, is the phase of sum w^4 over the four outermost points
//     (the diamond's tips).
//  3. Give each dot the id of the nearest turned layout position; every id must be taken once and
//     every dot lie within 0.3 pitch of its position.
//  4. The layout -> image homography of the matched dots must reproduce every dot to
//     max_layout_error_px, else the dots are not this pattern (a dot covered and a look-alike
//     taken in its place, two patterns, ...).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace cellmetry::dot {

struct PatternMatch {
  std::vector<int> chosen;  // indices into the input of the 13 dots kept (nearest the centre)
  std::vector<int> order;   // order[k]: index into the input of layout id k + 1
  Eigen::Matrix3d homography = Eigen::Matrix3d::Identity();  // layout mm -> the input's coords
  double max_error_px = 0.0;
  std::string failure;  // empty when matched
};

// `points` in the coordinates the homography is to map into (ideal pixels); `pitch_mm` scales
// the layout.
PatternMatch MatchDiamond(const std::vector<Eigen::Vector2d>& points, double pitch_mm,
                          double max_layout_error_px);

}  // namespace cellmetry::dot
