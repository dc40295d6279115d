// What a simulation draws at random: a truth around the nominal cell, and commands from a pose
// set (the 2023 delta report's section 6 setup, for any robot with inverse kinematics).
//
// Truth: every model length off by up to `dimensions_mm`, every angle (a delta's homing
// offsets) by up to `homing_increments` motor increments, each camera by up to `mm` and `rad`
// per axis (uniform).
//
// Pose sets (report, sec. 6.2), any size, inside the robot config's workspace cylinder; the
// commands are the nominal model's inverse kinematics of the drawn points, exactly as a
// controller that believes the nominal model would command them:
//   camera_view        uniform over the part of the workspace inside a camera's field of view
//   uniform_workspace  uniform over the whole cylinder
//   boundaries         uniform over the cylinder's surface (side, top and bottom by area)
#pragma once

#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

struct ModelErrors {
  double dimensions_mm = 0.0;
  double homing_increments = 0.0;
};

struct CameraErrors {
  double mm = 0.0;
  double rad = 0.0;
};

enum class PoseSet { kCameraView, kUniformWorkspace, kBoundaries };
std::string PoseSetName(PoseSet set);
// Raises InputError at `node` for an unknown name.
PoseSet ParsePoseSet(const ConfigNode& node);

struct PoseSetSpec {
  PoseSet set = PoseSet::kUniformWorkspace;
  int count = 125;
  std::string camera;  // camera_view: whose field of view ("" with one camera: that one)
};

// `nominal` plus the drawn errors, parameter by parameter (lengths in mm, angles in rad).
std::vector<double> DrawModelTruth(const RobotModel& model, const std::vector<double>& nominal,
                                   const ModelErrors& errors, std::mt19937& rng);

// exp(drawn rvec) R, t + drawn shift: the camera's true pose around its nominal one.
Pose DrawCameraTruth(const Pose& nominal, const CameraErrors& errors, std::mt19937& rng);

// Whether a point in a camera's axes (mm, z along the optical axis) lies inside a field of view
// of half angles `half_fov_rad` about the camera's x and y axes: the image's rectangle.
bool InFieldOfView(const Eigen::Vector2d& half_fov_rad, const Eigen::Vector3d& p_cam);

// Where a pose set may put the marker: the workspace of `model`, and for camera_view the cone
// of a camera with pose T_base_cam (nominal) and half field of view.
struct PoseSetGeometry {
  const RobotModel* model = nullptr;
  std::vector<double> nominal_values;
  Eigen::Vector3d marker_mm = Eigen::Vector3d::Zero();  // nominal marker on the flange
  bool camera_known = false;                            // camera_view needs one
  Pose T_base_cam;
  Eigen::Vector2d half_fov_rad = Eigen::Vector2d(0.629, 0.427);
  std::string origin;  // the robot config, for errors
};

// `count` commands; raises InputError when the set has no reachable point (in view).
std::vector<std::vector<double>> DrawPoseSet(const PoseSetGeometry& geometry, PoseSet set,
                                             int count, std::mt19937& rng);

}  // namespace cellmetry
