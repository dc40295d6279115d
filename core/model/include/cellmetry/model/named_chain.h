// NamedChain: a serial arm as its own description (a URDF) names and frames it, for exports that
// should keep the user's names. A robot model offers it through RobotModel::AsNamedChain
// (robot_model.h) when it was read from such a description; exports write it without knowing the
// model.
//
// The joints run from `base_link` (the model's base frame) to `tip_link` (its flange frame), each
// the child of the one before: the fixed ones as the description has them, the movable ones the
// model's joints in order, at the model's parameter values:
//
//   T_base_flange(q) = O_1 [Rot(axis_1, q_1)] O_2 [Rot(axis_2, q_2)] ... O_m
//
// where O_k is joint k's T_parent_child (its <origin>, with a movable joint's zero offset folded
// in, so that its value is the controller's reading) and the bracket is there for movable joints
// only. Lengths in mm; joint values in rad.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

struct NamedJointLimit {
  double lower_rad = 0.0;
  double upper_rad = 0.0;
  double effort = 0.0;  // as the description gives them (URDF: N m, rad/s)
  double velocity = 0.0;
};

struct NamedJoint {
  std::string name;
  std::string parent_link;
  std::string child_link;
  bool movable = false;                             // turns about `axis`; else fixed
  Pose T_parent_child = Pose::Identity();           // at joint value 0 (mm)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit, in the child link's frame
  std::optional<NamedJointLimit> limit;             // none: continuous
};

struct NamedChain {
  std::string base_link;
  std::string tip_link;
  std::vector<NamedJoint> joints;  // base_link to tip_link, in order
};

// The pose of tip_link in base_link at joint readings q (one per movable joint), by the product
// above.
Pose NamedChainTipPose(const NamedChain& chain, const double* q);

}  // namespace cellmetry
