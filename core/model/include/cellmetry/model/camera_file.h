// Camera calibration files: the three formats a user already has, read into a PinholeCamera.
//
//   ours     camera: {width: 1280, height: 800, fx: 880, fy: 880, cx: 639.5, cy: 399.5,
//                     distortion: [k1, k2, p1, p2, k3]}
//   OpenCV   cv::FileStorage YAML/XML (first line `%YAML` or `<?xml`) with image_width,
//            image_height, camera_matrix, distortion_coefficients, as OpenCV's calibration
//            sample writes it
//   ROS      a camera_info YAML as camera_calibration / camera_calibration_parsers write it:
//            image_width, image_height, camera_name, camera_matrix {rows, cols, data},
//            distortion_model (plumb_bob, or rational_polynomial whose extra three are zero),
//            distortion_coefficients {rows, cols, data}, rectification_matrix, projection_matrix
//
// The camera model is K with OpenCV's 5-coefficient distortion on raw (unrectified) images:
// cellmetry detects on the images as the camera took them. A ROS file's rectification and
// projection matrices describe the rectified view; ReadRosCameraInfo keeps them for a stereo
// rig's extrinsics (stereo.h), ReadCamera ignores them.
#pragma once

#include <string>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/model/camera.h"

namespace cellmetry {

// Reads any of the three formats; InputError naming the file, the line and the missing or
// malformed field otherwise.
PinholeCamera ReadCamera(const std::string& path);

// One camera block of our YAML ({width, height, fx, fy, cx, cy, distortion}).
PinholeCamera ReadCameraNode(const ConfigNode& node);

// A ROS camera_info file: the camera, and the rectified view it was calibrated with.
struct RosCameraInfo {
  PinholeCamera camera;
  Eigen::Matrix3d R_rect_camera = Eigen::Matrix3d::Identity();  // rectification_matrix
  Eigen::Matrix<double, 3, 4> P =
      Eigen::Matrix<double, 3, 4>::Zero();  // projection_matrix;
                                            // P(0,3) = -fx' baseline, the file's unit
};

// Whether `root` (a parsed YAML file) is a ROS camera_info file: it has camera_matrix and
// image_width at its top level.
bool IsRosCameraInfo(const ConfigNode& root);

// Reads a ROS camera_info file (IsRosCameraInfo); errors at the field's line and column.
RosCameraInfo ReadRosCameraInfo(const ConfigNode& root);

}  // namespace cellmetry
