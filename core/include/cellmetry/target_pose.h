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

// The target origin seen by a stereo rig. When both views have the keypoint `origin_id` and the
// layout puts it at the origin, that keypoint is triangulated. Otherwise every keypoint seen in
// both views is triangulated and the layout fitted to them (Kabsch); the origin's covariance is
// then the mean point covariance over the number of points (exact for points spread evenly
// around the origin, as a marker's corners are). None with fewer than 3 common keypoints.
std::optional<TriangulatedPoint> TargetOriginFromStereo(const StereoRig& rig,
                                                        const std::vector<Keypoint>& left,
                                                        const std::vector<Keypoint>& right,
                                                        const std::vector<MarkerPoint>& layout,
                                                        int origin_id);

}  // namespace cellmetry
