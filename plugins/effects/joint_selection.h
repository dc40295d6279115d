// Which joints a per-joint effect acts on (`joints: [2, 3]`, 1-based as in reports; default all),
// and the per-joint parameters it then has.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/basics/parameter.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry::effects {

// 0-based joint indices; an index outside the robot is an InputError at `joints:`.
std::vector<int> SelectJoints(const ConfigNode& config, const RobotModel& robot);

// One 1-based joint number (`from: 5`) as a 0-based index; outside the robot, an InputError at
// its node.
int SelectJoint(const ConfigNode& node, const RobotModel& robot);

// "j<i>.<what>" for each selected joint (1-based in the name).
std::string JointName(int joint);

// "joint 2" / "joints 2, 3".
std::string JointsInWords(const std::vector<int>& joints);

}  // namespace cellmetry::effects
