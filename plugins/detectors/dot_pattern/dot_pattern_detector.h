// The report's 13-dot pattern (Porée 2023, section 4.1, figures 10 and 11b) in the diamond layout
// of diamond_layout.h. Keypoint 0 is the pattern's centre, keypoints 1..13 its dots.
#pragma once

#include <optional>

#include "cellmetry/model/detector.h"
#include "dot_common/dot_finder.h"

namespace cellmetry::dot {

enum class PatternCentre {
  kHomography,  // the layout -> image homography applied to the origin: exact under perspective
  kMean,        // the report's mean of the 13 dots: exact only for a pattern parallel to the image
};

struct DotPatternOptions {
  double dot_diameter_mm = 6.0;
  double pitch_mm = 12.0;
  PatternCentre centre = PatternCentre::kHomography;
  double max_layout_error_px = 1.0;
  DotFinderOptions finder;
  std::optional<PinholeCamera> camera;
  // Each dot's perspective eccentricity corrected (circle_centre.h), the dots' tilt taken from the
  // pattern's own homography: needs the camera.
  bool perspective_correction = false;
};

class DotPatternDetector : public Detector {
 public:
  explicit DotPatternDetector(DotPatternOptions options);

  Detection Detect(const ImageView& image) override;
  const std::vector<MarkerPoint>& layout() const override { return layout_; }
  std::vector<MarkerFace> Faces(double texels_per_mm) const override;

 private:
  DotPatternOptions options_;
  DotFinder finder_;
  std::vector<MarkerPoint> layout_;
};

}  // namespace cellmetry::dot
