// UrdfChain: the revolute chain between two links of a URDF, as the `urdf` robot model needs it.
//
// Walking from `base_link` to `tip_link`, each revolute or continuous joint is one of the robot's
// joints, in chain order; fixed joints are folded into the origin of the next movable joint
// (T_previous_parent) or, past the last one, into T_last_joint_tip. For movable joint i:
//
//   T_base_tip(q) = ... T_previous_parent_i Trans(xyz_i) R_parent_joint_i Rot(axis_i, q_i) ...
//                   T_last_joint_tip
//
// where Trans(xyz_i) R_parent_joint_i is the joint's <origin xyz rpy> in its parent link and
// axis_i its <axis> in the joint frame (unit). Lengths in mm (the URDF's metres x 1000).
//
// Refused with an InputError located at the robot config's key: a URDF that cannot be read or
// parsed, a link that is not in it, a tip_link not below base_link, a prismatic, planar,
// floating or mimic joint on the chain, a chain without a movable joint.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/model/named_chain.h"

namespace cellmetry::urdf_robot {

struct UrdfJoint {
  std::string name;                           // the URDF joint's name
  Pose T_previous_parent = Pose::Identity();  // fixed joints since the previous movable joint
                                              // (or base_link), up to this joint's parent link
  Eigen::Vector3d xyz_mm = Eigen::Vector3d::Zero();              // <origin xyz>, in the parent link
  Eigen::Matrix3d R_parent_joint = Eigen::Matrix3d::Identity();  // <origin rpy>
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();               // <axis>, unit, in the joint frame
};

// A joint on the path from base_link to tip_link as the URDF has it, fixed ones included: what
// exports write back under the URDF's own names (RobotModel::AsNamedChain).
struct UrdfPathJoint {
  std::string name;
  std::string parent_link;
  std::string child_link;
  int movable = -1;                      // index into UrdfChain::joints; -1: a fixed joint
  Pose origin = Pose::Identity();        // a fixed joint's <origin> (mm)
  std::optional<NamedJointLimit> limit;  // a revolute joint's <limit>; none: continuous
};

struct UrdfChain {
  std::string file;  // the URDF, as resolved from the config
  std::string base_link;
  std::string tip_link;
  std::vector<UrdfJoint> joints;
  Pose T_last_joint_tip = Pose::Identity();  // fixed joints past the last movable one
  std::vector<UrdfPathJoint> path;           // base_link to tip_link
};

// Reads `file` (relative to the config), `base_link` and `tip_link` of a `urdf` robot config.
UrdfChain ReadUrdfChain(const ConfigNode& config);

}  // namespace cellmetry::urdf_robot
