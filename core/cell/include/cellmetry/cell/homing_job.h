// A homing job: the one job reader's file (job.h) with `job: homing`, one robot with inverse
// kinematics and no world target, its camera's calibrated pose under `cameras:`, the marker as
// its one tool, the noise under `noise:` and the options under `homing:` (homing.h).
#pragma once

#include <string>
#include <vector>

#include "cellmetry/cell/homing.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

struct HomingJob {
  WorkcellJob job;
  HomingArm arm;
  std::string robot, camera, target;  // names in the recording
  Eigen::Vector3d sigma_mm = Eigen::Vector3d::Zero();
  HomingOptions options;
};

// Raises InputError at the job's key for anything homing cannot use.
HomingJob LoadHomingJob(const std::string& path, Registry& registry);

// The recording's (command, measured position) pairs of the job's marker and camera.
std::vector<PointSample> CollectPoints(const HomingJob& job, const Recording& recording);

}  // namespace cellmetry
