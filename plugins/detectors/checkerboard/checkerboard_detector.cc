// The `checkerboard` detector (checkerboard_detector.h): findChessboardCornersSB, corners put in
// layout order; says why when the board is not found.
#include "checkerboard_detector.h"

#include <utility>

#include <opencv2/calib3d.hpp>

#include "corner_order.h"

namespace cellmetry::checkerboard {

CheckerboardDetector::CheckerboardDetector(CheckerboardOptions options)
    : options_(std::move(options)), layout_(Layout(options_.target)) {
  if (options_.normalize_image) flags_ |= cv::CALIB_CB_NORMALIZE_IMAGE;
  if (options_.exhaustive) flags_ |= cv::CALIB_CB_EXHAUSTIVE;
  if (options_.accuracy) flags_ |= cv::CALIB_CB_ACCURACY;
}

std::vector<MarkerFace> CheckerboardDetector::Faces(double texels_per_mm) const {
  return checkerboard::Faces(options_.target, texels_per_mm);
}

Detection CheckerboardDetector::Detect(const ImageView& image) {
  Detection out;
  if (image.empty()) {
    out.failure = "the image is empty";
    return out;
  }
  const CheckerboardTarget& t = options_.target;
  // findChessboardCornersSB only reads its input: wrap the caller's pixels.
  const cv::Mat gray(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.data),
                     static_cast<size_t>(image.stride));
  bool found = false;
  try {
    found = cv::findChessboardCornersSB(gray, cv::Size(t.corners_x, t.corners_y), corners_, flags_);
  } catch (const cv::Exception& e) {
    out.failure = "findChessboardCornersSB failed: " + e.msg;
    return out;
  }
  if (!found || static_cast<int>(corners_.size()) != t.corners()) {
    out.failure = "no " + std::to_string(t.corners_x) + " x " + std::to_string(t.corners_y) +
                  " inner-corner checkerboard found: the whole board must be in view, with white "
                  "paper around it (check corners_x and corners_y: inner corners, not squares)";
    return out;
  }
  ToLayoutOrder(gray, t.corners_x, t.corners_y, &corners_);
  const Eigen::Matrix2d covariance =
      options_.sigma_px * options_.sigma_px * Eigen::Matrix2d::Identity();
  for (int id = 0; id < t.corners(); ++id) {
    out.keypoints.push_back({id, Eigen::Vector2d(corners_[id].x, corners_[id].y), covariance});
  }
  return out;
}

}  // namespace cellmetry::checkerboard
