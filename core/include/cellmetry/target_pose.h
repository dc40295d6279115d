// Where a target is, from one camera's keypoints (PnP) or from two cameras' (triangulation).
//
// EstimateTargetPose: the target pose in a camera frame from its detected keypoints matched to
// the layout by id. OpenCV's solvePnP starts it (IPPE for coplanar layouts, Collins & Kneip
// 2014; EPnP otherwise), Gauss-Newton on the keypoint-covariance-weighted reprojection error
// finishes it, and (J^T W J)^-1 is the covariance of (rotation vector, translation).
#pragma once

#include <optional>
#include <vector>

#include "cellmetry/camera.h"
#include "cellmetry/detector.h"
#include "cellmetry/stereo.h"

namespace cellmetry {

struct TargetPose {
  Pose T_cam_target;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();  // rvec, t (mm)
  double reprojection_rms_px = 0.0;
  int points = 0;
};

// Needs 4 or more keypoints whose ids are in the layout; none otherwise.
std::optional<TargetPose> EstimateTargetPose(const PinholeCamera& camera,
                                             const std::vector<Keypoint>& keypoints,
                                             const std::vector<MarkerPoint>& layout);

// The target origin seen by a stereo rig: triangulates the keypoint with id `origin_id` when both
// views have it. None otherwise.
std::optional<TriangulatedPoint> TriangulateKeypoint(const StereoRig& rig,
                                                     const std::vector<Keypoint>& left,
                                                     const std::vector<Keypoint>& right,
                                                     int origin_id);

}  // namespace cellmetry
