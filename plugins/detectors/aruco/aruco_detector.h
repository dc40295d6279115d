// ArucoDetector: the `aruco` Detector. Finds the target's markers with OpenCV 4.6 contrib's
// cv::aruco::detectMarkers and reports their corners as keypoints (aruco_target.h for ids and
// frames). With the default corner_refinement (subpix) the plugin refines each marker itself:
//   1. edge refinement  each side fitted as a line through sub-pixel edge points, corners at the
//                       intersections (edge_lines.h). cornerSubPix is pulled ~0.2 px into the
//                       marker by blur (measured on rendered views); the lines are not.
//   2. cornerSubPix     (what CORNER_REFINE_SUBPIX does inside detectMarkers) where the lines
//                       find no clean edges, with its window shrunk to stay inside the marker's
//                       border cell: OpenCV's fixed 11 px window on 4 px cells snaps corners onto
//                       inner bits (up to 5 px off on OpenCV's own gboriginal.png).
//   A marker too small for the image's blur (edge_lines.h measures it) keeps detectMarkers'
//   corners: no window fits inside its border cell.
// Other OpenCV refinements (contour, apriltag) run inside detectMarkers as configured.
//
// Pixel convention: OpenCV's (centre of the top-left pixel at (0, 0)), as the contract wants, so
// corners pass through unchanged. The image is wrapped, not copied.
// Covariance model: every corner gets sigma_px^2 * I (isotropic, independent corners): the
// sub-pixel corner noise is nearly isotropic and OpenCV does not report a per-corner quality.
// A marker id seen twice in one image is ambiguous: both copies are left out.
#pragma once

#include <opencv2/aruco.hpp>

#include <string>
#include <vector>

#include "cellmetry/model/detector.h"
#include "aruco_target.h"
#include "fiducial_common/edge_lines.h"

namespace cellmetry::aruco {

struct ArucoOptions {
  ArucoTarget target;
  std::string dictionary_name;                        // for messages
  cv::Ptr<cv::aruco::DetectorParameters> parameters;  // for detectMarkers
  bool subpix = true;                                 // the plugin's own cornerSubPix stage
  int subpix_window_px = 5;                           // half-width at most
  int subpix_max_iterations = 50;
  double subpix_accuracy_px = 0.01;
  bool edge_refinement = true;
  double sigma_px = 0.1;
};

class ArucoDetector : public Detector {
 public:
  explicit ArucoDetector(ArucoOptions options);

  Detection Detect(const ImageView& image) override;
  const std::vector<MarkerPoint>& layout() const override { return layout_; }
  std::vector<MarkerFace> Faces(double texels_per_mm) const override;

 private:
  // The stages after detectMarkers, for one marker's corners.
  fiducial::Quad Refine(const cv::Mat& gray, const ImageView& image,
                        std::vector<cv::Point2f>* corners) const;

  ArucoOptions options_;
  std::vector<MarkerPoint> layout_;
  std::vector<bool> wanted_;  // by marker id: is it part of this target?
  // Scratch kept between calls (one Detector per thread).
  std::vector<std::vector<cv::Point2f>> corners_;
  std::vector<std::vector<cv::Point2f>> rejected_;
  std::vector<int> ids_;
};

}  // namespace cellmetry::aruco
