// `cellmetry export --format urdf`: a calibrated serial arm as a URDF (urdfdom parses it).
//
//   world --(fixed: T_world_base)--> <robot>_base --(<robot>_joint1: continuous about z)-->
//   <robot>_link1 ... <robot>_link<n> --(fixed: T_last_joint_flange)--> <robot>_flange
//   --(fixed: T_flange_tool)--> <tool>   (each tool the result fitted on this robot)
//
// Joint i's <origin> is the chain's T_parent_joint (serial_chain.h): the calibrated geometry
// with the joint's zero offset folded in, so a URDF joint value is the controller's reading and
// robot_state_publisher puts the flange where cellmetry's model does. Metres and radians (URDF's
// units), every digit a double has. The opening comment names what a URDF cannot hold (effects
// such as compliance, sigma) and lists the fitted parameters with their sigma; the joints carry
// no inertia, visuals or effort limits (cellmetry does not know them), and are `continuous`
// unless the robot config gives joint limits.
#pragma once

#include <string>

#include "cellmetry/exports/calibrated_cell.h"

namespace cellmetry {

// InputError when `robot` is no serial chain (a delta arm), naming what it can be exported as.
std::string UrdfExport(const CalibratedCell& cell, const CalibratedRobot& robot);

}  // namespace cellmetry
