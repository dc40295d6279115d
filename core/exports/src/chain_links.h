// Links and joints built from a calibrated SerialChain (serial_chain.h), under cellmetry's names
// (chain_links.cc) or ur_description's (ur_links.cc), for robot_links.h. With `chain` null only
// the ends (base_link, base_joint, T_base_link_base, flange_link) are filled.
#pragma once

#include <string>

#include "cellmetry/exports/robot_links.h"
#include "cellmetry/model/serial_chain.h"

namespace cellmetry {

// Joint `index` of the chain: turning about z, its origin the chain's T_parent_joint, limited
// when the robot config gives limits (effort and velocity unknown: 0).
LinkJoint ChainJoint(const CalibratedRobot& robot, const SerialChain& chain, size_t index,
                     const std::string& name, const std::string& parent_link,
                     const std::string& child_link);

RobotLinks CellmetryLinks(const CalibratedRobot& robot, const SerialChain* chain);

// InputError (exit code 2) unless `robot` is a serial chain of six revolute joints.
void CheckUrArm(const CalibratedCell& cell, const CalibratedRobot& robot);
RobotLinks UrLinks(const CalibratedRobot& robot, const SerialChain* chain);

}  // namespace cellmetry
