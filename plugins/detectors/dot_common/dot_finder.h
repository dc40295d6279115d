// The report's white-dot finder (Porée 2023, section 4.1, figure 11a) with the sub-pixel step
// done on gray levels, shared by the `dot` and `dot_pattern` detectors:
//
//   gamma + global threshold (binarize.h) -> white regions, size and circularity filter (blobs.h)
//   -> local black / white levels and 50 % edge crossings (edge_points.h)
//   -> ellipse fit to the crossings, centre covariance (ellipse_fit.h)
//
// Only the blobs' neighbourhoods are read after the threshold, and every buffer is kept between
// calls, so one finder per thread runs at frame rate.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/formats/image.h"
#include "dot_common/binarize.h"
#include "dot_common/blobs.h"
#include "dot_common/edge_points.h"
#include "dot_common/ellipse_fit.h"
#include "dot_common/image_geometry.h"

namespace cellmetry::dot {

struct DotFinderOptions {
  double gamma = 1.0;
  std::optional<double> threshold;  // corrected gray level; nullopt: automatic
  BlobFilter filter;
  double min_contrast = 40.0;   // gray levels between the local white and black
  double max_fit_rms_px = 0.3;  // RMS distance of the edge points to their ellipse
  EdgeMethod edge = EdgeMethod::kProfile;
};

struct Dot {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // ellipse centre, image pixels
  Eigen::Matrix2d covariance_px2 = Eigen::Matrix2d::Identity();
  Ellipse ellipse;  // in ideal pixels (image pixels without a distorted camera)
  LocalLevels levels;
  double area_px = 0.0;
};

// What one search found and why the rest was dropped.
struct DotSearch {
  std::vector<Dot> dots;
  std::string image_problem;  // e.g. "the image is empty"; then nothing else was tried
  BlobCounts blobs;
  int at_border = 0;
  int low_contrast = 0;
  int bad_fit = 0;
  int raw_threshold = 0;

  // "no blob passed the size and circularity filter (3 white regions: 2 too small, 1 not round)"
  std::string WhyNone() const;
};

class DotFinder {
 public:
  DotFinder(DotFinderOptions options, ImageGeometry geometry);

  // The dots of one image (the result is valid until the next call).
  const DotSearch& Find(const ImageView& image);

  const DotFinderOptions& options() const { return options_; }
  const ImageGeometry& geometry() const { return geometry_; }

 private:
  bool MeasureDot(const ImageView& image, const Blob& blob, Dot* dot);

  DotFinderOptions options_;
  ImageGeometry geometry_;
  GrayTransform transform_;
  BlobFinder blob_finder_;
  cv::Mat binary_;
  std::vector<Blob> blobs_;
  std::vector<Crossing> crossings_;
  std::vector<EdgePoint> edges_;
  DotSearch search_;
};

}  // namespace cellmetry::dot
