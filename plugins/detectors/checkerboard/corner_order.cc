// Checkerboard corners in layout order (corner_order.h): handedness, then colour.
#include "corner_order.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace cellmetry::checkerboard {
namespace {

float Cross(const cv::Point2f& a, const cv::Point2f& b) { return a.x * b.y - a.y * b.x; }

// Mean gray level of a 3 x 3 px patch (bilinear) at `centre`.
double Gray(const cv::Mat& gray, const cv::Point2f& centre) {
  cv::Mat patch;
  cv::getRectSubPix(gray, cv::Size(3, 3), centre, patch, CV_32F);
  return cv::mean(patch)[0];
}

}  // namespace

void ToLayoutOrder(const cv::Mat& gray, int corners_x, int corners_y,
                   std::vector<cv::Point2f>* corners) {
  auto at = [&](int col, int row) -> cv::Point2f& { return (*corners)[row * corners_x + col]; };
  // 1. Handedness, from the outermost corners (the longest baselines).
  const cv::Point2f along_row = at(corners_x - 1, 0) - at(0, 0);
  const cv::Point2f down_column = at(0, corners_y - 1) - at(0, 0);
  if (Cross(along_row, down_column) < 0) {
    for (int row = 0; row < corners_y / 2; ++row) {
      for (int col = 0; col < corners_x; ++col) {
        std::swap(at(col, row), at(col, corners_y - 1 - row));
      }
    }
  }
  // 2. Colour: (white-expected) - (black-expected) gray levels over every cell between corners.
  double contrast = 0.0;
  for (int row = 0; row + 1 < corners_y; ++row) {
    for (int col = 0; col + 1 < corners_x; ++col) {
      const cv::Point2f centre =
          0.25f * (at(col, row) + at(col + 1, row) + at(col, row + 1) + at(col + 1, row + 1));
      contrast += ((col + row) % 2 == 0 ? -1.0 : 1.0) * Gray(gray, centre);
    }
  }
  if (contrast < 0) std::reverse(corners->begin(), corners->end());
}

}  // namespace cellmetry::checkerboard
