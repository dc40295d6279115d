// Fields that jobs, simulation specs and comparison specs share: a pose, a recording folder,
// the kind of a job file. Each raises InputError at the node, with file:line:column.
#pragma once

#include <string>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/config_node.h"

namespace cellmetry {

// {xyz: [mm], rvec: [rad]}, both optional (identity where absent).
Pose ReadPose(const ConfigNode& node);

// A recording folder named at `node`, resolved against the file; InputError there if absent.
std::string ReadRecordingPath(const ConfigNode& node);

// The `job:` kind of a job file ("workcell", "kinematic", "homing").
std::string JobKind(const std::string& path);

}  // namespace cellmetry
