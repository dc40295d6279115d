// The report's white dot (Porée 2023, section 4.1): one white disk on a black square.
// Keypoint 0 is the image of the disk's centre.
#pragma once

#include <optional>

#include "cellmetry/model/detector.h"
#include "dot_common/dot_finder.h"

namespace cellmetry::dot {

struct DotDetectorOptions {
  double diameter_mm = 10.0;
  DotFinderOptions finder;
  std::optional<PinholeCamera> camera;
  // Perspective eccentricity correction (circle_centre.h): needs the camera, and the dot's normal
  // roughly (camera frame) to choose between the two tilts an ellipse allows.
  bool perspective_correction = false;
  Eigen::Vector3d dot_normal = -Eigen::Vector3d::UnitZ();
};

class DotDetector : public Detector {
 public:
  explicit DotDetector(DotDetectorOptions options);

  Detection Detect(const ImageView& image) override;
  const std::vector<MarkerPoint>& layout() const override { return layout_; }
  std::vector<MarkerFace> Faces(double texels_per_mm) const override;

 private:
  DotDetectorOptions options_;
  DotFinder finder_;
  std::vector<MarkerPoint> layout_;
};

}  // namespace cellmetry::dot
