// The `apriltag_board` detector (apriltag_detector.h): the AprilTag 3 library's tags of this board
// seen once, corners moved to OpenCV's convention and order and refined by edge lines.
#include "apriltag_detector.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fiducial_common/edge_lines.h"
#include "fiducial_common/id_list.h"

namespace cellmetry::apriltag_board {
namespace {

using fiducial::IdList;

// The library's detections of one image, by whether they belong to this board.
struct SortedDetections {
  std::vector<const apriltag_detection_t*> ours;  // this board's tags
  std::map<int, int> seen;                        // this board's ids: how often each was found
  std::vector<int> foreign;                       // ids of tags not on this board
};

SortedDetections SortByBoard(zarray_t* detections, const std::vector<bool>& wanted) {
  SortedDetections sorted;
  for (int i = 0; i < zarray_size(detections); ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(detections, i, &det);
    if (det->id < 0 || det->id >= static_cast<int>(wanted.size()) || !wanted[det->id]) {
      sorted.foreign.push_back(det->id);
      continue;
    }
    ++sorted.seen[det->id];
    sorted.ours.push_back(det);
  }
  return sorted;
}

// Why an image gave no usable tag: ids seen twice, only other boards' tags, or quads that did
// not decode.
std::string NoTagUsed(const std::string& family, const SortedDetections& sorted, int quads) {
  const std::string what = "no " + family + " tag of this board";
  std::vector<int> twice;
  for (const auto& [id, count] : sorted.seen) {
    if (count > 1) twice.push_back(id);
  }
  if (!twice.empty()) {
    return what + " could be used: tag ids " + IdList(twice) +
           " each appear more than once in the image";
  }
  if (!sorted.foreign.empty()) {
    std::vector<int> foreign = sorted.foreign;
    std::sort(foreign.begin(), foreign.end());
    return what + " found; the image shows other ids (" + IdList(foreign) +
           "): check first_id / cube_faces";
  }
  return what + " found: " + std::to_string(quads) + " quads, none decoded as a " + family + " tag";
}

}  // namespace

AprilTagDetector::AprilTagDetector(AprilTagOptions options, FamilyPtr family)
    : options_(std::move(options)), layout_(Layout(options_.board)), family_(std::move(family)),
      detector_(apriltag_detector_create()) {
  wanted_.assign(family_->ncodes, false);
  for (int id : options_.board.ids()) wanted_[id] = true;
  apriltag_detector_t* td = detector_.get();
  td->quad_decimate = options_.quad_decimate;
  td->quad_sigma = options_.quad_sigma;
  td->qtp.min_white_black_diff = options_.min_white_black_diff;
  td->refine_edges = options_.refine_edges;
  td->decode_sharpening = options_.decode_sharpening;
  td->nthreads = options_.nthreads;
  apriltag_detector_add_family_bits(td, family_.get(), options_.max_hamming);
}

std::vector<MarkerFace> AprilTagDetector::Faces(double texels_per_mm) const {
  return apriltag_board::Faces(options_.board, *family_, texels_per_mm);
}

Detection AprilTagDetector::Detect(const ImageView& image) {
  Detection out;
  if (image.empty()) {
    out.failure = "the image is empty";
    return out;
  }
  const DetectionsPtr detections = RunLibrary(image);
  const SortedDetections sorted = SortByBoard(detections.get(), wanted_);
  const Eigen::Matrix2d covariance =
      options_.sigma_px * options_.sigma_px * Eigen::Matrix2d::Identity();
  for (const apriltag_detection_t* det : sorted.ours) {
    if (sorted.seen.at(det->id) > 1) continue;
    const fiducial::Quad quad = Corners(*det, image);
    for (int k = 0; k < 4; ++k) out.keypoints.push_back({det->id * 4 + k, quad[k], covariance});
  }
  std::sort(out.keypoints.begin(), out.keypoints.end(),
            [](const Keypoint& a, const Keypoint& b) { return a.id < b.id; });
  if (out.keypoints.empty()) out.failure = NoTagUsed(options_.family, sorted, detector_->nquads);
  return out;
}

AprilTagDetector::DetectionsPtr AprilTagDetector::RunLibrary(const ImageView& image) {
  std::uint8_t* pixels = const_cast<std::uint8_t*>(image.data);  // the library only reads...
  if (options_.quad_sigma != 0.0f && options_.quad_decimate <= 1.0f) {
    // ...except here: it blurs the image it was given in place.
    scratch_.resize(static_cast<size_t>(image.stride) * image.height);
    std::memcpy(scratch_.data(), image.data, scratch_.size());
    pixels = scratch_.data();
  }
  image_u8_t frame{image.width, image.height, image.stride, pixels};
  return DetectionsPtr(apriltag_detector_detect(detector_.get(), &frame));
}

fiducial::Quad AprilTagDetector::Corners(const apriltag_detection_t& det, const ImageView& image) {
  // Library corner i: i = 0 bottom-left, 1 bottom-right, 2 top-right, 3 top-left (apriltag.c
  // projects (-1, 1), (1, 1), (1, -1), (-1, -1) of the tag, whose y points down the tag).
  fiducial::Quad quad;
  for (int k = 0; k < 4; ++k) {
    quad[k] = Eigen::Vector2d(det.p[3 - k][0] - 0.5, det.p[3 - k][1] - 0.5);
  }
  if (!options_.edge_refinement) return quad;
  // One cell of paper (or of the reversed border's black ring) lies outside every tag. A quad
  // the lines cannot refine keeps the library's corners: found on a decimated image, those of
  // the library at full resolution on a window around the tag.
  if (fiducial::RefineByEdgeLines(image, family_->width_at_border, 1.0, &quad) !=
          fiducial::EdgeRefinement::kRefined &&
      options_.quad_decimate > 1.0f && options_.redetect_unrefined) {
    RedetectAtFullResolution(image, det.id, &quad);
  }
  return quad;
}

bool AprilTagDetector::RedetectAtFullResolution(const ImageView& image, int id,
                                                fiducial::Quad* quad) {
  Eigen::Vector2d lo = (*quad)[0], hi = (*quad)[0];
  for (const auto& corner : *quad) lo = lo.cwiseMin(corner), hi = hi.cwiseMax(corner);
  // Half a side of margin: the tag's white (or black) ring and the library's threshold tiles.
  const double margin = 0.5 * (hi - lo).maxCoeff() + 8.0;
  const int x0 = std::max(0, static_cast<int>(std::floor(lo.x() - margin)));
  const int y0 = std::max(0, static_cast<int>(std::floor(lo.y() - margin)));
  const int x1 = std::min(image.width, static_cast<int>(std::ceil(hi.x() + margin)) + 1);
  const int y1 = std::min(image.height, static_cast<int>(std::ceil(hi.y() + margin)) + 1);
  if (x1 - x0 < 16 || y1 - y0 < 16) return false;
  const int w = x1 - x0, h = y1 - y0;
  std::uint8_t* corner =
      const_cast<std::uint8_t*>(image.data) + static_cast<size_t>(y0) * image.stride + x0;
  int stride = image.stride;
  if (options_.quad_sigma != 0.0f) {  // the library blurs an undecimated image in place
    scratch_.resize(static_cast<size_t>(w) * h);
    for (int row = 0; row < h; ++row) {
      std::memcpy(scratch_.data() + static_cast<size_t>(row) * w,
                  corner + static_cast<size_t>(row) * image.stride, w);
    }
    corner = scratch_.data();
    stride = w;
  }
  image_u8_t window{w, h, stride, corner};
  apriltag_detector_t* td = detector_.get();
  td->quad_decimate = 1.0f;
  const std::unique_ptr<zarray_t, DetectionsDeleter> detections(
      apriltag_detector_detect(td, &window));
  td->quad_decimate = options_.quad_decimate;
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  for (int i = 0; i < zarray_size(detections.get()); ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(detections.get(), i, &det);
    const Eigen::Vector2d c(det->c[0] + x0 - 0.5, det->c[1] + y0 - 0.5);
    if (det->id != id || (c - centre).norm() > 0.25 * (hi - lo).minCoeff()) continue;
    for (int k = 0; k < 4; ++k) {
      (*quad)[k] = Eigen::Vector2d(det->p[3 - k][0] + x0 - 0.5, det->p[3 - k][1] + y0 - 0.5);
    }
    return true;
  }
  return false;
}

}  // namespace cellmetry::apriltag_board
