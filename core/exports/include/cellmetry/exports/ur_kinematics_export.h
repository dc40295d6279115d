// `cellmetry export --format ur`: a calibrated six-joint arm as the kinematics YAML that Universal
// Robots' ROS description reads (ur_description's config/<model>/default_kinematics.yaml, passed
// as `kinematics_params_file` / `kinematics_parameters_file`):
//
//   kinematics:
//     shoulder:  {x, y, z, roll, pitch, yaw}     # metres, radians
//     upper_arm: ...   forearm: ...   wrist_1: ...   wrist_2: ...   wrist_3: ...
//     hash: calib_cellmetry_<16 hex digits>
//
// ur_description composes them as URDF joints: joint i's <origin xyz="x y z" rpy="roll pitch
// yaw"/> (fixed-axis: R = Rz(yaw) Ry(pitch) Rx(roll)) in the frame of joint i-1, starting at
// base_link_inertia (which is the controller's Base frame, ur_description's `base`), each joint
// turning about its z axis; then wrist_3_link -> flange (rpy 0 -pi/2 -pi/2) -> tool0 (rpy pi/2 0
// pi/2), which together are the identity: tool0 is wrist_3_link's frame. So section i is the
// chain's T_parent_joint (serial_chain.h), and the chain's flange must lie on the last axis
// (T_last_joint_flange a turn about and shift along it, folded into wrist_3); otherwise refused.
//
// The robot config's base and flange must be the controller's Base and tool0 frames (they are for
// configs/robots/ur3_vsb2020.yaml: the Huczala et al. table in UR's convention). `hash` is what the
// UR driver compares with the controller's own calibration checksum: ours cannot match it, and the
// driver says so in its log (the file is still used). The opening comment gives the base's
// placement in the world as the `origin` of ur_description's base_joint, the tools relative to
// tool0, and what the file cannot hold.
#pragma once

#include <string>

#include "cellmetry/exports/calibrated_cell.h"

namespace cellmetry {

// ur_description's section names, joint 1 to 6.
inline constexpr const char* kUrKinematicsSections[6] = {"shoulder", "upper_arm", "forearm",
                                                         "wrist_1",  "wrist_2",   "wrist_3"};

// InputError when `robot` is no serial chain of six joints with its flange on the last axis.
std::string UrKinematicsExport(const CalibratedCell& cell, const CalibratedRobot& robot);

}  // namespace cellmetry
