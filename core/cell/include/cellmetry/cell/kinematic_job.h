// Jobs for robots measured by marker positions (docs/formats.md, docs/delta.md):
//
//   job: kinematic   calibrate the robot model, camera pose and marker (kinematic_calibration.h)
//   job: homing      find the homing offsets of a calibrated arm (homing.h)
//
// Shared sections: `robot: {name, model, free}`, `camera: {name, xyz, rvec, free}`,
// `target:` (the marker), `noise: {position_mm: [x, y, depth]}`, `recording:`, `output:`.
#pragma once

#include <optional>
#include <string>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/cell/homing.h"
#include "cellmetry/cell/kinematic_problem.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

struct KinematicJob {
  std::string file;
  std::string recording;
  std::optional<std::string> validation_recording;  // fresh positions to score the result on
  std::string output;
  KinematicProblem problem;
  std::string solver_type;
  std::optional<ConfigNode> solver_config;
};

struct HomingJob {
  std::string file;
  std::string recording;
  std::string output;
  KinematicProblem problem;   // geometry, camera pose (required) and marker of the arm
  Eigen::Vector3d sigma_mm = Eigen::Vector3d::Zero();
  HomingOptions options;
};

KinematicJob LoadKinematicJob(const std::string& path, Registry& registry);
HomingJob LoadHomingJob(const std::string& path, Registry& registry);

}  // namespace cellmetry
