// ChArUco corners refined by cornerSubPix to the plugin's accuracy (corner_subpix.h).
#include "corner_subpix.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace cellmetry::charuco {

int RefineCorners(const cv::Mat& gray, const SubpixOptions& options,
                  std::vector<cv::Point2f>* corners) {
  const std::vector<cv::Point2f> found = *corners;
  const cv::TermCriteria stop(cv::TermCriteria::MAX_ITER | cv::TermCriteria::EPS,
                              options.max_iterations, options.accuracy_px);
  int refined = 0;
  for (size_t i = 0; i < found.size(); ++i) {
    // The nearest other corner: about a square away (under perspective, the nearer side).
    double square_px = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < found.size(); ++j) {
      if (j == i) continue;
      square_px = std::min(square_px, static_cast<double>(cv::norm(found[j] - found[i])));
    }
    if (!std::isfinite(square_px)) continue;
    const int half =
        std::min(options.max_half_px, static_cast<int>(options.clear_fraction * square_px - 1.0));
    if (half < 2) continue;
    std::vector<cv::Point2f> one = {found[i]};
    cv::cornerSubPix(gray, one, cv::Size(half, half), cv::Size(-1, -1), stop);
    (*corners)[i] = one[0];
    ++refined;
  }
  return refined;
}

}  // namespace cellmetry::charuco
