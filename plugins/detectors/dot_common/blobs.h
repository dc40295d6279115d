// White blobs of the binary image, filtered by size and circularity (Porée 2023, section 4.1,
// figure 11a: "contours of the shapes are extracted [Suzuki and Abe 1985], filtered based on their
// size and circularity").
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace cellmetry::dot {

struct Blob {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  // Covariance of the region (px^2): a uniform ellipse with semi-axes a, b has eigenvalues
  // a^2/4, b^2/4, so (p - centroid)^T (4 moments)^-1 (p - centroid) = 1 is its outline.
  Eigen::Matrix2d moments = Eigen::Matrix2d::Identity();
  double area_px = 0.0;  // pixel count
  // 4 pi area / perimeter^2 of the curve through the border pixels' centres (perimeter by
  // Vossepoel-Smeulders): 1 for a disk, 0.93 for one tilted 50 degrees, pi / 4 for a square.
  double circularity = 0.0;
};

struct BlobFilter {
  double min_area_px = 30.0;
  double max_area_px = 50000.0;
  double min_circularity = 0.8;
};

// Why blobs were dropped, for failure messages.
struct BlobCounts {
  int white_regions = 0;
  int too_small = 0;
  int too_large = 0;
  int not_round = 0;
};

// Finds the outer borders of white regions (Suzuki-Abe border following, cv::findContours with a
// two-level hierarchy: a white dot inside a black square inside a white sheet is still an outer
// border, a black hole in a white region is not). Keeps scratch buffers between calls.
class BlobFinder {
 public:
  void Find(const cv::Mat& binary, const BlobFilter& filter, std::vector<Blob>* blobs,
            BlobCounts* counts);

 private:
  std::vector<std::vector<cv::Point>> contours_;
  std::vector<cv::Vec4i> hierarchy_;
};

}  // namespace cellmetry::dot
