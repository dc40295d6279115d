// AprilTagDetector: the `apriltag_board` Detector, around one apriltag_detector_t of the
// AprilTag 3 C library (apriltag.h). The core makes one Detector per thread; the library's
// detector is not thread-safe, and each owns its family instance (tag_family.h).
//
// Pixel convention: the library puts (0, 0) at the top-left pixel's corner; the contract wants
// OpenCV's (its centre), so 0.5 px is subtracted from both coordinates (DESIGN.md). Corners are
// reordered from the library's (bottom-left first, counter-clockwise in the image) to OpenCV's
// order of tag_board.h. Then, by default, each side is fitted as a line through sub-pixel edge
// points and the corners put where the lines meet (edge_lines.h): the library's corners are off
// by 0.1-0.3 px, differently per corner, on blurred views.
// Covariance model: sigma_px^2 * I for every corner (the library reports no per-corner quality).
// The image is wrapped, not copied, except when quad_sigma != 0 without decimation: the library
// then blurs its input in place (apriltag.c, apriltag_detector_detect), so a scratch copy is
// made. A tag id seen twice in one image is ambiguous: both copies are left out.
// Decimation (quad_decimate, default 2) finds quads on a half-size image; the library decodes and
// (refine_edges) fits their edges at full resolution, and the edge lines refine the corners on
// the full image. A tag the lines cannot refine (cells too narrow for the blur, kTooSmall) would
// keep the decimated detection's corners, worse than the full-resolution library's on small
// tags: the library is run again at full resolution on a window around it (redetect_unrefined).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cellmetry/model/detector.h"
#include "fiducial_common/edge_lines.h"
#include "tag_board.h"
#include "tag_family.h"

namespace cellmetry::apriltag_board {

struct AprilTagOptions {
  std::string family = "tag36h11";
  TagBoard board;
  float quad_decimate = 2.0f;
  float quad_sigma = 0.0f;
  int min_white_black_diff = 20;  // the library's 5 lets sensor noise through as edges
  bool refine_edges = true;
  double decode_sharpening = 0.25;
  int nthreads = 1;
  int max_hamming = 1;
  bool edge_refinement = true;
  bool redetect_unrefined =
      true;  // decimated tags the edge lines leave: library at full resolution
  double sigma_px = 0.1;
};

class AprilTagDetector : public Detector {
 public:
  // `family` must be CreateFamily(options.family).
  AprilTagDetector(AprilTagOptions options, FamilyPtr family);

  Detection Detect(const ImageView& image) override;
  const std::vector<MarkerPoint>& layout() const override { return layout_; }
  std::vector<MarkerFace> Faces(double texels_per_mm) const override;

 private:
  struct DetectionsDeleter {
    void operator()(zarray_t* detections) const { apriltag_detections_destroy(detections); }
  };
  using DetectionsPtr = std::unique_ptr<zarray_t, DetectionsDeleter>;

  // The library's detections in `image` (wrapped, or copied where the library would blur it).
  DetectionsPtr RunLibrary(const ImageView& image);
  // One detection's corners in OpenCV's pixels and order, refined as the options say.
  fiducial::Quad Corners(const apriltag_detection_t& det, const ImageView& image);
  // The library's corners of tag `id` at full resolution, from a window around `quad` (OpenCV
  // pixels); false, `quad` unchanged, when the window shows no such tag there.
  bool RedetectAtFullResolution(const ImageView& image, int id, fiducial::Quad* quad);

  struct DetectorDeleter {
    void operator()(apriltag_detector_t* td) const { apriltag_detector_destroy(td); }
  };

  AprilTagOptions options_;
  std::vector<MarkerPoint> layout_;
  std::vector<bool> wanted_;  // by tag id
  // Declared before detector_, so that the detector, which refers to the family, is destroyed
  // first.
  FamilyPtr family_;
  std::unique_ptr<apriltag_detector_t, DetectorDeleter> detector_;
  std::vector<std::uint8_t> scratch_;  // the copy the library may blur
};

}  // namespace cellmetry::apriltag_board
