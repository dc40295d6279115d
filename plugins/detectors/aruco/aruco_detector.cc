// The `aruco` detector (aruco_detector.h): OpenCV's detectMarkers, this target's markers seen once
// kept, corners refined by edge lines or a shrunk cornerSubPix; says why when none is found.
#include "aruco_detector.h"

#include <algorithm>
#include <map>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "fiducial_common/edge_lines.h"
#include "fiducial_common/id_list.h"

namespace cellmetry::aruco {
namespace {

using fiducial::IdList;

}  // namespace

ArucoDetector::ArucoDetector(ArucoOptions options)
    : options_(std::move(options)), layout_(Layout(options_.target)) {
  wanted_.assign(options_.target.dictionary->bytesList.rows, false);
  for (int id : options_.target.ids()) wanted_[id] = true;
}

std::vector<MarkerFace> ArucoDetector::Faces(double texels_per_mm) const {
  return aruco::Faces(options_.target, texels_per_mm);
}

fiducial::Quad ArucoDetector::Refine(const cv::Mat& gray, const ImageView& image,
                                     std::vector<cv::Point2f>* corners) const {
  const int cells = options_.target.cells();
  fiducial::Quad quad;
  for (int k = 0; k < 4; ++k) quad[k] = Eigen::Vector2d((*corners)[k].x, (*corners)[k].y);
  if (options_.edge_refinement) {
    // Between markers of a board the paper may be narrower than a cell.
    const double clear =
        options_.target.board()
            ? std::min(1.0, options_.target.separation_mm / options_.target.cell_mm())
            : 1.0;
    const fiducial::EdgeRefinement result = fiducial::RefineByEdgeLines(image, cells, clear, &quad);
    // Refined: the lines' corners supersede cornerSubPix's. Too small for the blur: so is
    // cornerSubPix's window, keep detectMarkers' corners.
    if (result != fiducial::EdgeRefinement::kFailed) return quad;
  }
  // The window's half-width stays 2.5 px (a blurred edge's reach) short of the border cell's
  // inner edge; markers with smaller cells keep detectMarkers' corners.
  const double cell_px = 0.25 * cv::arcLength(*corners, true) / cells;
  const int half = std::min(static_cast<int>(cell_px - 2.5), options_.subpix_window_px);
  if (options_.subpix && half >= 2) {
    cv::cornerSubPix(gray, *corners, cv::Size(half, half), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::MAX_ITER | cv::TermCriteria::EPS,
                                      options_.subpix_max_iterations, options_.subpix_accuracy_px));
    for (int k = 0; k < 4; ++k) quad[k] = Eigen::Vector2d((*corners)[k].x, (*corners)[k].y);
  }
  return quad;
}

Detection ArucoDetector::Detect(const ImageView& image) {
  Detection out;
  if (image.empty()) {
    out.failure = "the image is empty";
    return out;
  }
  // detectMarkers only reads its input: wrap the caller's pixels instead of copying them.
  const cv::Mat gray(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.data),
                     static_cast<size_t>(image.stride));
  cv::aruco::detectMarkers(gray, options_.target.dictionary, corners_, ids_, options_.parameters,
                           rejected_);
  std::map<int, int> seen;  // id -> count
  for (int id : ids_) ++seen[id];
  const Eigen::Matrix2d covariance =
      options_.sigma_px * options_.sigma_px * Eigen::Matrix2d::Identity();
  std::vector<int> foreign;
  for (size_t i = 0; i < ids_.size(); ++i) {
    const int id = ids_[i];
    if (id < 0 || id >= static_cast<int>(wanted_.size()) || !wanted_[id]) {
      foreign.push_back(id);
      continue;
    }
    if (seen[id] > 1) continue;
    const fiducial::Quad quad = Refine(gray, image, &corners_[i]);
    for (int k = 0; k < 4; ++k) out.keypoints.push_back({id * 4 + k, quad[k], covariance});
  }
  std::sort(out.keypoints.begin(), out.keypoints.end(),
            [](const Keypoint& a, const Keypoint& b) { return a.id < b.id; });
  if (!out.keypoints.empty()) return out;

  const std::string what = "no " + options_.dictionary_name + " marker of this target";
  std::vector<int> twice;
  for (const auto& [id, count] : seen) {
    if (count > 1 && id < static_cast<int>(wanted_.size()) && wanted_[id]) twice.push_back(id);
  }
  if (!twice.empty()) {
    out.failure = what + " could be used: marker ids " + IdList(twice) +
                  " each appear more than once in the image";
  } else if (!foreign.empty()) {
    std::sort(foreign.begin(), foreign.end());
    out.failure = what + " found; the image shows other ids (" + IdList(foreign) +
                  "): check dictionary, marker_ids or first_id";
  } else {
    out.failure = what + " found: " + std::to_string(rejected_.size()) +
                  " square candidates, none decoded as a marker";
  }
  return out;
}

}  // namespace cellmetry::aruco
