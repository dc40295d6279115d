// The white-dot finder (dot_finder.h): threshold and blobs, then local levels, edge points and an
// ellipse per blob, counting why blobs were dropped to say why no dot was found.
#include "dot_common/dot_finder.h"

#include <Eigen/Dense>

#include <sstream>

namespace cellmetry::dot {

std::string DotSearch::WhyNone() const {
  if (!image_problem.empty()) return image_problem;
  std::ostringstream s;
  if (blobs.white_regions == 0) {
    s << "no white region above the threshold (gray level " << raw_threshold << ")";
    return s.str();
  }
  const int passed = blobs.white_regions - blobs.too_small - blobs.too_large - blobs.not_round;
  if (passed == 0) {
    s << "no blob passed the size and circularity filter (" << blobs.white_regions
      << " white regions: " << blobs.too_small << " too small, " << blobs.too_large
      << " too large, " << blobs.not_round << " not round)";
  } else {
    s << "no blob was a white dot on black: of " << passed << " round blobs, " << at_border
      << " touch the image border, " << low_contrast << " lack contrast to their surround, "
      << bad_fit << " have an outline that is not an ellipse";
  }
  return s.str();
}

DotFinder::DotFinder(DotFinderOptions options, ImageGeometry geometry)
    : options_(options), geometry_(std::move(geometry)),
      transform_(GrayTransform::Gamma(options.gamma)) {}

bool DotFinder::MeasureDot(const ImageView& image, const Blob& blob, Dot* dot) {
  if (!MeasureLocalLevels(image, transform_, blob, &dot->levels)) {
    ++search_.at_border;
    return false;
  }
  if (dot->levels.contrast() < options_.min_contrast) {
    ++search_.low_contrast;
    return false;
  }
  FindEdgePoints(image, transform_, blob, options_.edge, &dot->levels, &crossings_, &edges_);
  Eigen::Matrix2d to_ideal = Eigen::Matrix2d::Identity();
  if (geometry_.distorted()) {
    // The dot is small: one Jacobian at its centroid carries the search directions over.
    to_ideal = geometry_.IdealJacobian(blob.centroid);
    for (auto& e : edges_) {
      e.pixel = geometry_.ToIdeal(e.pixel);
      e.direction = to_ideal * e.direction;
    }
  }
  const std::optional<Ellipse> ellipse = FitEllipse(edges_);
  if (!ellipse || ellipse->rms_px > options_.max_fit_rms_px ||
      (ellipse->centre - (geometry_.distorted() ? geometry_.ToIdeal(blob.centroid) : blob.centroid))
              .norm() > ellipse->MinorRadius()) {
    ++search_.bad_fit;
    return false;
  }
  dot->ellipse = *ellipse;
  dot->pixel = geometry_.ToImage(ellipse->centre);
  const Eigen::Matrix2d back = to_ideal.inverse();
  dot->covariance_px2 = back * ellipse->centre_covariance * back.transpose();
  dot->area_px = blob.area_px;
  return true;
}

const DotSearch& DotFinder::Find(const ImageView& image) {
  std::vector<Dot> dots = std::move(search_.dots);  // keeps its capacity between frames
  dots.clear();
  search_ = DotSearch();
  search_.dots = std::move(dots);
  if (image.empty()) {
    search_.image_problem = "the image is empty";
    return search_;
  }
  const ThresholdResult threshold = ChooseThreshold(
      image, transform_, options_.threshold,
      static_cast<int>(options_.filter.min_area_px / 8));  // half the smallest dot, sampled 1 in 4
  search_.raw_threshold = threshold.raw_threshold;
  const double range = transform_.level[threshold.max_raw] - transform_.level[threshold.min_raw];
  if (range < options_.min_contrast) {
    std::ostringstream s;
    s << "the image has no contrast (gray levels " << threshold.min_raw << " to "
      << threshold.max_raw << ", min_contrast " << options_.min_contrast << ")";
    search_.image_problem = s.str();
    return search_;
  }
  Binarize(image, threshold.raw_threshold, &binary_);
  blob_finder_.Find(binary_, options_.filter, &blobs_, &search_.blobs);
  for (const Blob& blob : blobs_) {
    Dot dot;
    if (MeasureDot(image, blob, &dot)) search_.dots.push_back(dot);
  }
  return search_;
}

}  // namespace cellmetry::dot
