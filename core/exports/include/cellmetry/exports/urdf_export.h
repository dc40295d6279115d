// `cellmetry export --format urdf`: a calibrated serial arm as a URDF (urdfdom parses it).
//
// Under cellmetry's names (a robot model without names of its own, robot_links.h):
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
//
// A robot model with names of its own (a `urdf` robot) keeps them: its links and joints from
// base_link to tip_link, fixed ones included, with their axes and limits as read and the
// calibrated origins; world --(fixed)--> base_link, tools on tip_link. `--names ur` writes
// ur_description's names and frames (robot_links.h, ur_links.cc).
#pragma once

#include <string>

#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/exports/robot_links.h"

namespace cellmetry {

// InputError when `robot` is no serial chain (a delta arm), naming what it can be exported as.
// `naming` as robot_links.h says; `ur` refused for an arm that has not six joints.
std::string UrdfExport(const CalibratedCell& cell, const CalibratedRobot& robot,
                       ExportNaming naming = ExportNaming::kModel);

}  // namespace cellmetry
