// `cellmetry export --format tf`: every frame the result identified, as ROS 2 static transforms
// in a launch file (`ros2 launch <file>`), one tf2_ros static_transform_publisher node each:
//
//   <node pkg="tf2_ros" exec="static_transform_publisher" name="cellmetry_<child>"
//         args="--x X --y Y --z Z --qx QX --qy QY --qz QZ --qw QW
//               --frame-id <parent> --child-frame-id <child>"/>
//
// metres and a unit quaternion (qw >= 0), every digit a double has; frame names as ros_names.h
// says (world, cameras, tools), a robot's base and flange as its URDF export names them
// (robot_links.h: <robot>_base and <robot>_flange, a urdf robot's base_link and tip_link, or
// base_link and tool0 under ur_description's names, base_link then placed at T_world_base Rz(pi)).
// Each node is preceded by a comment with the frame's sigma (mm, rad about the parent's axes;
// "held" where the job held it). With several robots the comment block at the end gives each
// robot's base in every other's, with sigma propagated from both bases and their correlation
// (relative_pose.h); they are not published, since each base already hangs from the world and a
// tf frame has one parent.
#pragma once

#include <string>

#include "cellmetry/exports/calibrated_cell.h"

namespace cellmetry {

// `ur_robot`: the robot named as ur_description does (`--names ur`; "" = none): its base hangs
// from the world as base_link, its tools from tool0.
std::string TfLaunchExport(const CalibratedCell& cell, const std::string& ur_robot = "");

}  // namespace cellmetry
