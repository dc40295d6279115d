// StereoRig: two calibrated cameras and where the right one is relative to the left, and
// triangulation of a keypoint seen by both, with the 3x3 covariance of the point.
//
// Triangulate() is the maximum-likelihood point: it minimises the reprojection error in both
// images weighted by each keypoint's pixel covariance (Gauss-Newton from the midpoint of the two
// rays), and its covariance is (J^T W J)^-1, the pixel noise propagated through the stereo
// geometry. Along the optical axis it grows with Z^2 / (f b), as the report's eq. 8.1.3 implies
// (Z = f b / disparity), without needing rectified images.
//
// Files (ReadStereoRig): our YAML
//   stereo: {left: {<camera as in camera_file.h>}, right: {...},
//            T_right_left: {xyz: [-75, 0, 0], rvec: [0, 0, 0]}}   # p_right = T * p_left
// where left and right may also be calibration files (ours, OpenCV's or ROS camera_info); for
// two ROS camera_info files from camera_calibration's stereo output T_right_left may be left out
// and comes from their rectification and projection matrices, with `units: {length: m}` (the
// calibration's baseline unit);
// or OpenCV's stereo calibration (FileStorage with M1 D1 M2 D2 R T image_width image_height, as
// the stereo_calib sample writes them; T in the calibration's unit, here mm).
#pragma once

#include <optional>
#include <string>

#include "cellmetry/model/camera.h"
#include "cellmetry/model/detector.h"

namespace cellmetry {

struct StereoRig {
  PinholeCamera left;
  PinholeCamera right;
  Pose T_right_left;  // maps left-camera coordinates into the right camera
};

struct TriangulatedPoint {
  Eigen::Vector3d p_left_mm = Eigen::Vector3d::Zero();  // in the left camera's frame
  Eigen::Matrix3d covariance_mm2 = Eigen::Matrix3d::Zero();
  double reprojection_rms_px = 0.0;
};

// None when the rays are (near) parallel or the point lands behind a camera.
std::optional<TriangulatedPoint> Triangulate(const StereoRig& rig, const Keypoint& left,
                                             const Keypoint& right);

StereoRig ReadStereoRig(const std::string& path);

// The report's rig: two OakDLikeCamera()s 75 mm apart along x.
StereoRig OakDLikeRig();

}  // namespace cellmetry
