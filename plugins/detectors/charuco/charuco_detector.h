// CharucoDetector: the `charuco` Detector. OpenCV 4.6 contrib's pipeline for a ChArUco board:
//   1. cv::aruco::detectMarkers      the board's markers (ids of other boards are left out);
//   2. refineDetectedMarkers         (refine_markers) markers missed in 1. looked for again where
//                                    the board's found markers say they must be;
//   3. interpolateCornersCharuco     each chessboard corner between found markers, by the local
//                                    homography of its neighbouring markers (no camera needed),
//                                    then cornerSubPix on the chessboard corner itself;
//   4. corner_subpix.h               OpenCV's 0.5 px shift taken off (charuco_detector.cc), and
//                                    cornerSubPix run on to subpix_accuracy_px.
// Keypoints are the interpolated chessboard corners (charuco_target.h for ids and frame). Unlike
// `checkerboard`, a board partly hidden or cut by the image border gives the corners it shows.
//
// Pixel convention: OpenCV's (centre of the top-left pixel at (0, 0)), as the contract wants.
// Covariance model: sigma_px^2 * I for every corner (OpenCV reports no per-corner quality).
// The image is wrapped, not copied.
#pragma once

#include <opencv2/aruco/charuco.hpp>

#include <string>
#include <vector>

#include "cellmetry/model/detector.h"
#include "charuco_target.h"
#include "corner_subpix.h"

namespace cellmetry::charuco {

struct CharucoOptions {
  CharucoTarget target;
  std::string dictionary_name;  // for messages
  bool refine_markers = true;
  int min_markers = 2;       // interpolateCornersCharuco's: neighbouring markers a corner needs
  bool subpix = true;        // the plugin's own last cornerSubPix (corner_subpix.h)
  int subpix_window_px = 5;  // half-width at most
  int subpix_max_iterations = 50;
  double subpix_accuracy_px = 0.01;
  double sigma_px = 0.1;
};

class CharucoDetector : public Detector {
 public:
  explicit CharucoDetector(CharucoOptions options);

  Detection Detect(const ImageView& image) override;
  const std::vector<MarkerPoint>& layout() const override { return layout_; }
  std::vector<MarkerFace> Faces(double texels_per_mm) const override;

 private:
  // Why no corner was interpolated, in words.
  std::string Failure(const std::vector<int>& foreign) const;

  CharucoOptions options_;
  cv::Ptr<cv::aruco::CharucoBoard> board_;
  cv::Ptr<cv::aruco::DetectorParameters> parameters_;
  std::vector<MarkerPoint> layout_;
  SubpixOptions subpix_;
  // Scratch kept between calls (one Detector per thread).
  std::vector<std::vector<cv::Point2f>> marker_corners_;
  std::vector<std::vector<cv::Point2f>> rejected_;
  std::vector<int> marker_ids_;
  std::vector<cv::Point2f> corners_;
  std::vector<int> corner_ids_;
};

}  // namespace cellmetry::charuco
