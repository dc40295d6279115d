// Gamma table, threshold and binary image (binarize.h): the automatic threshold halfway between
// the median and the bright level of a histogram of every other row and column.
#include "dot_common/binarize.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace cellmetry::dot {

GrayTransform GrayTransform::Gamma(double gamma) {
  GrayTransform t;
  for (int i = 0; i < 256; ++i) {
    t.level[i] = static_cast<float>(gamma == 1.0 ? i : 255.0 * std::pow(i / 255.0, gamma));
  }
  return t;
}

ThresholdResult ChooseThreshold(const ImageView& image, const GrayTransform& transform,
                                std::optional<double> corrected_threshold, int bright_samples) {
  ThresholdResult result;
  std::array<int, 256> counts{};
  int total = 0;
  for (int y = 0; y < image.height; y += 2) {
    const std::uint8_t* row = image.data + static_cast<size_t>(y) * image.stride;
    for (int x = 0; x < image.width; x += 2) ++counts[row[x]];
    total += (image.width + 1) / 2;
  }
  result.min_raw = 0;
  while (result.min_raw < 255 && counts[result.min_raw] == 0) ++result.min_raw;
  result.max_raw = 255;
  while (result.max_raw > 0 && counts[result.max_raw] == 0) --result.max_raw;
  double level = 0.0;
  if (corrected_threshold) {
    level = *corrected_threshold;
  } else {
    int median = 0;
    for (int seen = counts[0]; 2 * seen < total; seen += counts[++median]) {
    }
    int bright = 255;
    for (int seen = counts[255]; seen < std::max(bright_samples, 1) && bright > 0;
         seen += counts[--bright]) {
    }
    level = 0.5 * (transform.level[median] + transform.level[bright]);
  }
  int raw = 0;
  while (raw + 1 < 256 && transform.level[raw + 1] <= level) ++raw;
  result.raw_threshold = raw;
  return result;
}

void Binarize(const ImageView& image, int raw_threshold, cv::Mat* binary) {
  const cv::Mat input(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.data),
                      static_cast<size_t>(image.stride));
  cv::threshold(input, *binary, raw_threshold, 255, cv::THRESH_BINARY);
}

}  // namespace cellmetry::dot
