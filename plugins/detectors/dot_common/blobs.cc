// White blobs (blobs.h): outer borders by cv::findContours, filtered by pixel area and by
// circularity (Vossepoel-Smeulders perimeter), with their centroid and second moments.
#include "dot_common/blobs.h"

#include <opencv2/imgproc.hpp>

#include <Eigen/Dense>
#include <cmath>

namespace cellmetry::dot {
namespace {

// Length of the curve an 8-connected chain digitises (Vossepoel and Smeulders, "Vector code
// probability and metrication error in the representation of straight lines of finite length",
// CGIP 20, 1982): 0.980 per axis step, 1.406 per diagonal step, -0.091 per change of step. The
// plain chain length (1 and sqrt 2) overestimates a circle's perimeter by about 5 %, which would
// cap a perfect dot's circularity near 0.9.
double ChainLength(const std::vector<cv::Point>& chain) {
  const size_t n = chain.size();
  if (n < 2) return 0.0;
  int axis = 0, diagonal = 0, corners = 0;
  cv::Point previous = chain[0] - chain[n - 1];
  for (size_t i = 0; i < n; ++i) {
    const cv::Point step = chain[(i + 1) % n] - chain[i];
    (std::abs(step.x) + std::abs(step.y) == 1 ? axis : diagonal) += 1;
    corners += step != previous;
    previous = step;
  }
  return 0.980 * axis + 1.406 * diagonal - 0.091 * corners;
}

}  // namespace

void BlobFinder::Find(const cv::Mat& binary, const BlobFilter& filter, std::vector<Blob>* blobs,
                      BlobCounts* counts) {
  blobs->clear();
  *counts = BlobCounts();
  contours_.clear();
  hierarchy_.clear();
  cv::findContours(binary, contours_, hierarchy_, cv::RETR_CCOMP, cv::CHAIN_APPROX_NONE);
  for (size_t i = 0; i < contours_.size(); ++i) {
    if (hierarchy_[i][3] >= 0) continue;  // a hole's border, not a white region's
    ++counts->white_regions;
    const std::vector<cv::Point>& contour = contours_[i];
    // The polygon through the border pixels' centres; Pick's theorem turns its area into the
    // pixel count (area + boundary points / 2 + 1), which is what a user measures.
    const double polygon_area = std::abs(cv::contourArea(contour));
    const double area = polygon_area + 0.5 * static_cast<double>(contour.size()) + 1.0;
    if (area < filter.min_area_px) {
      ++counts->too_small;
      continue;
    }
    if (area > filter.max_area_px) {
      ++counts->too_large;
      continue;
    }
    const double perimeter = ChainLength(contour);
    const double circularity =
        perimeter > 0 ? 4.0 * M_PI * polygon_area / (perimeter * perimeter) : 0;
    if (circularity < filter.min_circularity) {
      ++counts->not_round;
      continue;
    }
    const cv::Moments m = cv::moments(contour);
    Blob blob;
    if (m.m00 > 0) {
      blob.centroid = Eigen::Vector2d(m.m10 / m.m00, m.m01 / m.m00);
      blob.moments << m.mu20 / m.m00, m.mu11 / m.m00, m.mu11 / m.m00, m.mu02 / m.m00;
    }
    // A line has no second dimension to walk across (only reachable with min_circularity ~ 0).
    if (!(m.m00 > 0) || !(blob.moments.determinant() > 1e-6)) {
      ++counts->not_round;
      continue;
    }
    blob.area_px = area;
    blob.circularity = circularity;
    blobs->push_back(blob);
  }
}

}  // namespace cellmetry::dot
