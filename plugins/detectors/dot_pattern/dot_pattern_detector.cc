#include "dot_pattern_detector.h"

#include <Eigen/Dense>

#include <sstream>

#include "diamond_layout.h"
#include "dot_common/circle_centre.h"
#include "dot_common/disk_texture.h"
#include "homography.h"
#include "pattern_matcher.h"

namespace cellmetry::dot {
namespace {

// The pattern plane's normal (camera frame, toward the camera) from a layout -> ideal pixel
// homography: K^-1 H = [r1 r2 t] up to scale (Zhang 2000, section 2.3 / 3.1).
Eigen::Vector3d PlaneNormal(const Eigen::Matrix3d& h, const ImageGeometry& geometry) {
  const Eigen::Matrix3d m = geometry.IdealFromNormalised().inverse() * h;
  Eigen::Vector3d r1 = m.col(0).normalized(), r2 = m.col(1).normalized();
  Eigen::Vector3d t = m.col(2) / m.col(0).norm();
  if (t.z() < 0.0) r1 = -r1, r2 = -r2, t = -t;
  Eigen::Vector3d n = r1.cross(r2).normalized();
  if (n.dot(t) > 0.0) n = -n;
  return n;
}

}  // namespace

DotPatternDetector::DotPatternDetector(DotPatternOptions options)
    : options_(std::move(options)), finder_(options_.finder, ImageGeometry(options_.camera)) {
  layout_.push_back({0, Eigen::Vector3d::Zero()});
  const auto& grid = DiamondGrid();
  for (int k = 0; k < kPatternDots; ++k) {
    layout_.push_back({k + 1, Eigen::Vector3d(grid[k].x(), grid[k].y(), 0.0) * options_.pitch_mm});
  }
}

std::vector<MarkerFace> DotPatternDetector::Faces(double texels_per_mm) const {
  // Black one dot diameter beyond the outermost dots' edges.
  const double side = 4.0 * options_.pitch_mm + 3.0 * options_.dot_diameter_mm;
  std::vector<Eigen::Vector2d> centres;
  for (const auto& g : DiamondGrid()) centres.push_back(g * options_.pitch_mm);
  return {DiskFace(side, options_.dot_diameter_mm, centres, texels_per_mm)};
}

Detection DotPatternDetector::Detect(const ImageView& image) {
  Detection detection;
  const auto& camera = options_.camera;
  if (camera && !image.empty()) {
    detection.failure = camera->SizeMismatch(image.width, image.height);
    if (!detection.failure.empty()) return detection;
  }
  const DotSearch& search = finder_.Find(image);
  const int found = static_cast<int>(search.dots.size());
  if (found < kPatternDots) {
    std::ostringstream s;
    s << found << " of 13 dots found";
    if (found == 0) s << ": " << search.WhyNone();
    detection.failure = s.str();
    return detection;
  }
  const ImageGeometry& geometry = finder_.geometry();
  std::vector<Eigen::Vector2d> ideal;
  for (const Dot& d : search.dots) ideal.push_back(d.ellipse.centre);
  PatternMatch match = MatchDiamond(ideal, options_.pitch_mm, options_.max_layout_error_px);
  if (!match.failure.empty()) {
    detection.failure = match.failure;
    return detection;
  }

  // The dots, in layout order; corrected for perspective with the plane's tilt when asked.
  std::vector<Keypoint> dots(kPatternDots);
  std::vector<Eigen::Vector2d> plane, corrected;
  const Eigen::Vector3d normal = options_.perspective_correction
                                     ? PlaneNormal(match.homography, geometry)
                                     : Eigen::Vector3d::Zero();
  for (int k = 0; k < kPatternDots; ++k) {
    const Dot& dot = search.dots[match.order[k]];
    dots[k].id = k + 1;
    dots[k].pixel = dot.pixel;
    dots[k].covariance_px2 = dot.covariance_px2;
    Eigen::Vector2d at = dot.ellipse.centre;
    if (options_.perspective_correction) {
      const std::optional<Circle3d> circle =
          CircleNearest(dot.ellipse, geometry, options_.dot_diameter_mm / 2, normal);
      if (!circle) {
        detection.failure = "dot " + std::to_string(k + 1) +
                            "'s ellipse admits no circle for the perspective correction";
        return detection;
      }
      const Eigen::Vector3d c =
          geometry.IdealFromNormalised() * (circle->centre_mm / circle->centre_mm.z());
      at = c.head<2>();
      dots[k].pixel = camera->Project(circle->centre_mm);
    }
    plane.push_back(DiamondGrid()[k] * options_.pitch_mm);
    corrected.push_back(at);
  }

  // The centre: the report's mean of the dots, or the homography's image of the layout's origin.
  // The mean is the centre's image only while the pattern is parallel to the image (perspective
  // moves it by 0.23 px at 20 degrees of tilt and 450 mm); the homography's is exact, and about
  // 25 % noisier at that parallel pose, where the perspective it fits is pure noise.
  Keypoint centre;
  centre.id = 0;
  centre.covariance_px2.setZero();
  if (options_.centre == PatternCentre::kMean) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : corrected) mean += p;
    centre.pixel = geometry.ToImage(mean / kPatternDots);
    for (const auto& d : dots) centre.covariance_px2 += d.covariance_px2;
    centre.covariance_px2 /= kPatternDots * kPatternDots;
  } else {
    const std::optional<Eigen::Matrix3d> h = options_.perspective_correction
                                                 ? FitHomography(plane, corrected)
                                                 : std::optional<Eigen::Matrix3d>(match.homography);
    if (!h) {
      detection.failure = "ambiguous pattern: no homography maps the layout onto the dots";
      return detection;
    }
    const Eigen::Vector2d at = ApplyHomography(*h, Eigen::Vector2d::Zero());
    centre.pixel = geometry.ToImage(at);
    // First-order propagation of each dot's covariance through the fit (forward differences).
    constexpr double kStep = 1e-3;  // px
    for (int k = 0; k < kPatternDots; ++k) {
      Eigen::Matrix2d j;
      for (int axis = 0; axis < 2; ++axis) {
        std::vector<Eigen::Vector2d> moved = corrected;
        moved[k](axis) += kStep;
        const std::optional<Eigen::Matrix3d> hk = FitHomography(plane, moved);
        j.col(axis) =
            hk ? Eigen::Vector2d((ApplyHomography(*hk, Eigen::Vector2d::Zero()) - at) / kStep)
               : Eigen::Vector2d::Zero();
      }
      centre.covariance_px2 += j * dots[k].covariance_px2 * j.transpose();
    }
  }
  detection.keypoints.push_back(centre);
  for (const auto& d : dots) detection.keypoints.push_back(d);
  return detection;
}

}  // namespace cellmetry::dot
