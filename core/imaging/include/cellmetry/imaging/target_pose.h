// Where a target is, from one camera's keypoints (PnP) or from two cameras' (triangulation).
//
// EstimateTargetPose: the target pose in a camera frame from its detected keypoints matched to
// the layout by id. OpenCV's solvePnP starts it (IPPE when the matched points are coplanar, in
// whatever plane, Collins & Kneip 2014; EPnP otherwise), Gauss-Newton on the keypoint-covariance-
// weighted reprojection error finishes it. Keypoints the pose cannot explain (a tag half hidden
// by the robot, a corner seen edge-on) are dropped one at a time, worst first, and the pose
// refitted. The covariance of (rotation vector, translation) is (J^T W J)^-1 times the
// a-posteriori variance factor chi^2 / dof when that exceeds 1 (the keypoints were noisier than
// the detector said).
#pragma once

#include <optional>
#include <vector>

#include "cellmetry/imaging/stereo.h"
#include "cellmetry/model/camera.h"
#include "cellmetry/model/detector.h"

namespace cellmetry {

struct PoseEstimationOptions {
  // A keypoint whose whitened squared reprojection error exceeds this is an outlier: 28 is the
  // chi-square (2 dof) quantile at 1e-6, 5.3 sigma.
  double outlier_chi2 = 28.0;
  int min_points = 4;  // outliers are dropped only while more than this many remain
};

struct TargetPose {
  Pose T_cam_target;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();  // rvec, t (mm)
  double normalized_reprojection_rms = 0.0;  // in keypoint sigmas: ~1 when as noisy as claimed
  double variance_factor = 1.0;              // the covariance's inflation (>= 1)
  int points = 0;                            // keypoints used
  int rejected = 0;                          // keypoints dropped as outliers
};

// Needs 4 or more keypoints whose ids are in the layout; none otherwise.
std::optional<TargetPose> EstimateTargetPose(const PinholeCamera& camera,
                                             const std::vector<Keypoint>& keypoints,
                                             const std::vector<MarkerPoint>& layout,
                                             const PoseEstimationOptions& options = {});

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
