// SerialChain: a serial arm as the chain of revolute joints that URDF, ROS and robot vendors'
// kinematics files hold. A robot model offers it through RobotModel::AsSerialChain
// (robot_model.h); exports (core/exports) write it in their formats without knowing the model.
//
//   T_base_flange(q) = T_base_joint1 Rz(q_1) T_joint1_joint2 Rz(q_2) ... T_joint(n-1)_jointn
//   Rz(q_n)
//                      T_jointn_flange
//
// Joint i turns by the controller's reading q_i (rad) about the z axis of its own frame, whose
// place at q_i = 0 in the frame of joint i-1 (the base for joint 1) is T_parent_joint[i]. Whatever
// else the model has per joint that is rigid (a twist, a tilt, a zero offset added to the reading)
// is folded into these origins, so that the chain reproduces the model's T_base_flange exactly.
// What a chain cannot hold (a reading scaled by a gear ratio, anything that is not rigid) the
// model names in `not_expressible`, for the file's comments. Lengths in mm.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

struct SerialChain {
  std::vector<Pose> T_parent_joint;  // one per joint, at q_i = 0 (mm)
  Pose T_last_joint_flange = Pose::Identity();
  std::vector<std::string> not_expressible;  // what of the model the chain leaves out, in words
};

// The chain's flange pose at joint readings q (num joints entries), by the product above.
Pose ChainFlangePose(const SerialChain& chain, const double* q);

// Rz(angle): the turn of a joint about its axis.
Pose TurnAboutZ(double angle_rad);

}  // namespace cellmetry
