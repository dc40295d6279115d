// Camera intrinsics from views of a flat calibration board (`cellmetry calibrate-camera`).
//
// A detector plugin (checkerboard, charuco, any whose layout is flat: z = 0) finds the board's
// keypoints in each image; OpenCV's calibrateCamera (Zhang's method, then Levenberg-Marquardt on
// the reprojection error) fits fx, fy, cx, cy and the 5-coefficient distortion k1 k2 p1 p2 k3,
// the model PinholeCamera and the camera files use (camera_file.h). What it reports with them:
//   rms_px          the RMS reprojection error over every keypoint of every view used;
//   views[i].rms_px each view's RMS (a view much worse than the rest: a blurred or bent board,
//                   a wrong detection);
//   sigma           each intrinsic's standard deviation: OpenCV's stdDeviationsIntrinsics,
//                   the square roots of the diagonal of (J^T J)^-1 scaled by the residuals'
//                   variance (sum of squares over observations minus parameters). They assume
//                   independent keypoint noise and no model error: a lower bound on what
//                   another set of views would give.
// A view is left out (skipped, with the reason) when its image cannot be read, yields fewer than
// min_keypoints keypoints, or has another size than the first view that shows the board.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "cellmetry/basics/error.h"
#include "cellmetry/model/camera.h"
#include "cellmetry/model/detector.h"

namespace cellmetry {

struct CameraCalibrationOptions {
  int min_keypoints = 6;          // per view
  bool fix_aspect_ratio = false;  // fx / fy held at its start (CALIB_FIX_ASPECT_RATIO)
  bool zero_tangential = false;   // p1 = p2 = 0 (CALIB_ZERO_TANGENT_DIST)
  bool fix_k3 = false;            // k3 = 0 (CALIB_FIX_K3): few views, or a narrow lens
  SourceLocation detector_at;     // where the detector was configured, for errors
};

struct CalibrationView {
  std::string path;
  int keypoints = 0;
  double rms_px = 0.0;
};

struct CameraCalibration {
  PinholeCamera camera;
  // Standard deviations of fx, fy, cx, cy (px) and k1, k2, p1, p2, k3; 0 for a held parameter
  // (with the aspect ratio held, fx's is fy's times the ratio).
  std::array<double, 9> sigma{};
  double rms_px = 0.0;
  std::vector<CalibrationView> views;                        // used
  std::vector<std::pair<std::string, std::string>> skipped;  // path, why
};

// Names of the sigma entries, in order: fx, fy, cx, cy, k1, k2, p1, p2, k3.
const std::array<const char*, 9>& IntrinsicNames();
// A camera's values in that order.
std::array<double, 9> IntrinsicValues(const PinholeCamera& camera);

// InputError when the layout is not flat, or fewer than 3 views remain.
CameraCalibration CalibrateCamera(Detector& detector, const std::vector<std::string>& image_paths,
                                  const CameraCalibrationOptions& options = {});

// The camera file (camera_file.h's own format) with the calibration's figures as comments above
// it: ReadCamera reads the camera back, a person reads the rest.
std::string CameraFileText(const CameraCalibration& calibration);

}  // namespace cellmetry
