// The `charuco` detector (charuco_detector.h): markers, then the chessboard corners between
// them; says why when none is found.
#include "charuco_detector.h"

#include <algorithm>
#include <utility>

#include "corner_subpix.h"
#include "fiducial_common/id_list.h"

namespace cellmetry::charuco {
namespace {

// OpenCV contrib 4.6's interpolateCornersCharuco hands cornerSubPix its corners shifted by
// -0.5 px and adds 0.5 px to what cornerSubPix returns; cornerSubPix converges to the corner
// wherever it starts, so every corner comes back 0.5 px right and down of the corner in OpenCV's
// own pixel convention (on rendered views each view's mean was +0.47..+0.54 px in x and in y).
// Taken off.
constexpr float kSubpixShiftPx = 0.5f;

}  // namespace

CharucoDetector::CharucoDetector(CharucoOptions options)
    : options_(std::move(options)), board_(MakeBoard(options_.target)),
      parameters_(cv::aruco::DetectorParameters::create()),
      layout_(Layout(*board_, options_.target.square_mm)) {
  subpix_.clear_fraction =
      0.5 * (options_.target.square_mm - options_.target.marker_mm) / options_.target.square_mm;
  subpix_.max_half_px = options_.subpix_window_px;
  subpix_.max_iterations = options_.subpix_max_iterations;
  subpix_.accuracy_px = options_.subpix_accuracy_px;
}

std::vector<MarkerFace> CharucoDetector::Faces(double texels_per_mm) const {
  return charuco::Faces(options_.target, *board_, texels_per_mm);
}

std::string CharucoDetector::Failure(const std::vector<int>& foreign) const {
  const std::string what =
      "no chessboard corner of this " + options_.dictionary_name + " ChArUco board";
  if (marker_ids_.empty() && !foreign.empty()) {
    return what + " found; the image shows other marker ids (" + fiducial::IdList(foreign) +
           "): check dictionary, squares_x and squares_y";
  }
  if (marker_ids_.empty()) {
    return what + " found: " + std::to_string(rejected_.size()) +
           " square candidates, none decoded as one of its markers";
  }
  return what + " found: " + std::to_string(marker_ids_.size()) +
         " of its markers seen, too few next to any corner (min_markers: " +
         std::to_string(options_.min_markers) + ")";
}

Detection CharucoDetector::Detect(const ImageView& image) {
  Detection out;
  if (image.empty()) {
    out.failure = "the image is empty";
    return out;
  }
  // The aruco functions only read their input: wrap the caller's pixels.
  const cv::Mat gray(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.data),
                     static_cast<size_t>(image.stride));
  cv::aruco::detectMarkers(gray, options_.target.dictionary, marker_corners_, marker_ids_,
                           parameters_, rejected_);
  // Markers of another board (ids past this one's) would be matched to no square.
  std::vector<int> foreign;
  size_t kept = 0;
  for (size_t i = 0; i < marker_ids_.size(); ++i) {
    if (marker_ids_[i] >= options_.target.markers()) {
      foreign.push_back(marker_ids_[i]);
      continue;
    }
    marker_ids_[kept] = marker_ids_[i];
    marker_corners_[kept] = marker_corners_[i];
    ++kept;
  }
  marker_ids_.resize(kept);
  marker_corners_.resize(kept);
  std::sort(foreign.begin(), foreign.end());
  if (options_.refine_markers && !marker_ids_.empty()) {
    cv::aruco::refineDetectedMarkers(gray, board_, marker_corners_, marker_ids_, rejected_);
  }
  corners_.clear();
  corner_ids_.clear();
  if (!marker_ids_.empty()) {
    cv::aruco::interpolateCornersCharuco(marker_corners_, marker_ids_, gray, board_, corners_,
                                         corner_ids_, cv::noArray(), cv::noArray(),
                                         options_.min_markers);
  }
  if (corner_ids_.empty()) {
    out.failure = Failure(foreign);
    return out;
  }
  // OpenCV's shift off first (kSubpixShiftPx), so that the last refinement starts where the
  // corner is.
  for (cv::Point2f& corner : corners_) corner -= cv::Point2f(kSubpixShiftPx, kSubpixShiftPx);
  if (options_.subpix) RefineCorners(gray, subpix_, &corners_);
  const Eigen::Matrix2d covariance =
      options_.sigma_px * options_.sigma_px * Eigen::Matrix2d::Identity();
  for (size_t i = 0; i < corner_ids_.size(); ++i) {
    out.keypoints.push_back(
        {corner_ids_[i], Eigen::Vector2d(corners_[i].x, corners_[i].y), covariance});
  }
  std::sort(out.keypoints.begin(), out.keypoints.end(),
            [](const Keypoint& a, const Keypoint& b) { return a.id < b.id; });
  return out;
}

}  // namespace cellmetry::charuco
