// A last cornerSubPix on ChArUco corners, to the accuracy the plugin asks for.
//
// Why: OpenCV 4.6's interpolateCornersCharuco runs cornerSubPix with DetectorParameters'
// defaults, which stop once a step is under 0.1 px (cornerRefinementMinAccuracy): on rendered
// views its corners were up to 0.2 px off, where the saddle point itself is found to a few
// hundredths. Started from its corners, cornerSubPix runs on until steps are under
// accuracy_px.
//
// The window: a chessboard corner is clear of other edges for (square - marker) / 2 along the
// board's axes, up to the neighbouring markers' sides. That distance in pixels is taken from the
// nearest other corner found (one square away, or more where corners are missing); the
// half-width is at most max_half_px and stays 1 px inside it. A corner with no other corner
// found, or too small for a 2 px half-width, keeps OpenCV's position.
#pragma once

#include <opencv2/core.hpp>

#include <vector>

namespace cellmetry::charuco {

struct SubpixOptions {
  double clear_fraction = 0.0;  // (square_mm - marker_mm) / 2 / square_mm
  int max_half_px = 5;
  int max_iterations = 50;
  double accuracy_px = 0.01;
};

// Refines `corners` (OpenCV pixels) in place; returns how many were refined.
int RefineCorners(const cv::Mat& gray, const SubpixOptions& options,
                  std::vector<cv::Point2f>* corners);

}  // namespace cellmetry::charuco
