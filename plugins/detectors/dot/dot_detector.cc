// The `dot` detector (dot_detector.h): the one dot the finder returns, its centre corrected for
// perspective when asked; no dot or several dots is a failure.
#include "dot_detector.h"

#include <sstream>

#include "dot_common/circle_centre.h"
#include "dot_common/disk_texture.h"

namespace cellmetry::dot {

DotDetector::DotDetector(DotDetectorOptions options)
    : options_(std::move(options)), finder_(options_.finder, ImageGeometry(options_.camera)) {
  layout_.push_back({0, Eigen::Vector3d::Zero()});
}

std::vector<MarkerFace> DotDetector::Faces(double texels_per_mm) const {
  // The black square reaches one diameter beyond the dot's edge on every side: the sub-pixel
  // step reads the black level in a ring out to about 1.8 radii.
  const double side = 2.0 * options_.diameter_mm;
  return {DiskFace(side, options_.diameter_mm, {Eigen::Vector2d::Zero()}, texels_per_mm)};
}

Detection DotDetector::Detect(const ImageView& image) {
  Detection detection;
  const auto& camera = options_.camera;
  if (camera && !image.empty()) {
    detection.failure = camera->SizeMismatch(image.width, image.height);
    if (!detection.failure.empty()) return detection;
  }
  const DotSearch& search = finder_.Find(image);
  if (search.dots.empty()) {
    detection.failure = search.WhyNone();
    return detection;
  }
  if (search.dots.size() > 1) {
    std::ostringstream s;
    s.precision(1);
    s << std::fixed << search.dots.size() << " dots found, the target has 1: ambiguous (at";
    for (const Dot& d : search.dots) s << " (" << d.pixel.x() << ", " << d.pixel.y() << ")";
    s << "); cover the others or narrow min_area_px / max_area_px";
    detection.failure = s.str();
    return detection;
  }
  const Dot& dot = search.dots.front();
  Keypoint k;
  k.id = 0;
  k.pixel = dot.pixel;
  k.covariance_px2 = dot.covariance_px2;
  if (options_.perspective_correction) {
    const std::optional<Circle3d> circle = CircleNearest(
        dot.ellipse, finder_.geometry(), options_.diameter_mm / 2, options_.dot_normal);
    if (!circle) {
      detection.failure = "the dot's ellipse admits no circle for the perspective correction";
      return detection;
    }
    // The correction is a fraction of a pixel and smooth: the ellipse centre's covariance stands.
    k.pixel = camera->Project(circle->centre_mm);
  }
  detection.keypoints.push_back(k);
  return detection;
}

}  // namespace cellmetry::dot
