// Detector: the contract of a detector plugin (white dot, 13-dot pattern, ArUco, AprilTag, ...).
//
// A detector finds its marker in one 8-bit grayscale image and returns keypoints: an id, a pixel
// (OpenCV convention: the centre of the top-left pixel is (0, 0)) and the pixel covariance of
// that keypoint. It also describes its marker as printed, so that the core can render it and
// estimate poses without knowing it:
//   layout()  the keypoints' positions on the target (mm, target frame), by id;
//   Faces()   the printed faces: each a flat texture placed in the target frame.
// One Detector object is used by one thread at a time; the core makes one per thread (the
// AprilTag library's detector is not thread-safe), so Detect() may keep scratch state.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/image.h"

namespace cellmetry {

struct Keypoint {
  int id = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance_px2 = Eigen::Matrix2d::Identity();
};

struct Detection {
  std::vector<Keypoint> keypoints;
  std::string failure;  // empty when found; else why not, in words ("no dot passed the ...")
  bool found() const { return failure.empty(); }
};

struct MarkerPoint {
  int id = 0;
  Eigen::Vector3d p_target_mm = Eigen::Vector3d::Zero();
};

// A flat printed face: texture texel (i, j) covers [i, i+1) x [j, j+1) * mm_per_texel in the
// face's x, y; the face's frame sits at T_target_face, its z = 0 plane is the paper and its z axis
// points out of the printed side (OpenCV's marker convention): a camera sees the face only from
// that side.
struct MarkerFace {
  Pose T_target_face = Pose::Identity();
  GrayImage texture;  // 0 black .. 255 white
  double mm_per_texel = 0.1;
};

class Detector {
 public:
  virtual ~Detector() = default;
  virtual Detection Detect(const ImageView& image) = 0;
  virtual const std::vector<MarkerPoint>& layout() const = 0;
  // The faces with at least `texels_per_mm` texture resolution (for supersampled rendering).
  virtual std::vector<MarkerFace> Faces(double texels_per_mm) const = 0;
};

}  // namespace cellmetry
