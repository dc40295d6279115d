// CheckerboardDetector: the `checkerboard` Detector. Finds the board's inner corners with OpenCV's
// cv::findChessboardCornersSB (Duda and Frese 2018: a localized Radon transform, sub-pixel
// corners without cornerSubPix) and reports them in layout order (corner_order.h) as keypoints,
// ids as checkerboard_target.h numbers them.
//
// The whole board must be in view: findChessboardCornersSB reports all corners or none, so a
// board cut by the image border, or partly hidden, is not found (use `charuco` for that).
// Pixel convention: OpenCV's (centre of the top-left pixel at (0, 0)), as the contract wants.
// Covariance model: sigma_px^2 * I for every corner (OpenCV reports no per-corner quality).
// The image is wrapped, not copied.
#pragma once

#include <opencv2/core.hpp>

#include <vector>

#include "cellmetry/model/detector.h"
#include "checkerboard_target.h"

namespace cellmetry::checkerboard {

struct CheckerboardOptions {
  CheckerboardTarget target;
  bool normalize_image = false;  // CALIB_CB_NORMALIZE_IMAGE: costs accuracy (plugin.cc)
  bool exhaustive = false;       // CALIB_CB_EXHAUSTIVE
  bool accuracy = true;          // CALIB_CB_ACCURACY
  double sigma_px = 0.1;
};

class CheckerboardDetector : public Detector {
 public:
  explicit CheckerboardDetector(CheckerboardOptions options);

  Detection Detect(const ImageView& image) override;
  const std::vector<MarkerPoint>& layout() const override { return layout_; }
  std::vector<MarkerFace> Faces(double texels_per_mm) const override;

 private:
  CheckerboardOptions options_;
  std::vector<MarkerPoint> layout_;
  int flags_ = 0;                     // findChessboardCornersSB's
  std::vector<cv::Point2f> corners_;  // scratch kept between calls (one Detector per thread)
};

}  // namespace cellmetry::checkerboard
