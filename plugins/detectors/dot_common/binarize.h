// The report's first two steps (Porée 2023, section 4.1, figure 11a): gamma correction of the gray
// levels, then one global threshold that separates the white dots from everything else.
//
// Gamma is monotonic, so thresholding the corrected image equals thresholding the raw image at the
// raw level that maps to the threshold: the corrected image is never computed, only a 256-entry
// table, which the sub-pixel step (edge_points.h) also reads its gray levels through.
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <optional>

#include "cellmetry/formats/image.h"

namespace cellmetry::dot {

// Raw 8-bit level -> corrected level 255 * (raw / 255)^gamma.
struct GrayTransform {
  std::array<float, 256> level{};
  static GrayTransform Gamma(double gamma);
};

struct ThresholdResult {
  int raw_threshold = 0;         // white is raw > raw_threshold
  int min_raw = 0, max_raw = 0;  // darkest and brightest level seen (on the sampled grid)
};

// Chooses the raw threshold: `corrected_threshold` (a corrected gray level) when given, else
// automatically, halfway between the median (the background: a marker covers a small part of
// the frame) and the brightest level that at least `bright_samples` sampled pixels reach (the
// white of the smallest dot; fewer pixels are hot pixels or glints). Otsu's method was tried and
// fails here: a 15 px dot is 0.02 % of the frame, and splitting the background's own illumination
// gradient then wins. The histogram samples every other row and column: the threshold only has to
// split white from the rest, and the sub-pixel step never uses it.
ThresholdResult ChooseThreshold(const ImageView& image, const GrayTransform& transform,
                                std::optional<double> corrected_threshold, int bright_samples);

// binary = 255 where raw > raw_threshold, else 0 (no copy of the input).
void Binarize(const ImageView& image, int raw_threshold, cv::Mat* binary);

}  // namespace cellmetry::dot
