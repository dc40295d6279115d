// A calibrated robot as the links and joints a URDF holds, under the names an export asks for
// (`cellmetry export --names`), and the two frames tf hangs the rest of the cell from:
//
//   model   the robot model's own names when it has them (RobotModel::AsNamedChain: a `urdf`
//           robot's links and joints, fixed ones included, axes and limits as read, calibrated
//           origins); otherwise cellmetry's (ros_names.h): <robot>_base, <robot>_joint<i>,
//           <robot>_link<i>, <robot>_flange
//   ur      ur_description's, for a six-joint arm (ur_links.cc): base_link, base_link_inertia
//           (cellmetry's base frame), shoulder_pan_joint ... wrist_3_joint, shoulder_link ...
//           wrist_3_link, flange and tool0 (cellmetry's flange frame)
//
// Either way the chain is checked against the model's forward kinematics (robot_chain.h), and
// tools hang from `flange_link`, whose pose is cellmetry's flange. Lengths in mm.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/model/named_chain.h"

namespace cellmetry {

enum class ExportNaming { kModel, kUr };

// "model", "ur".
const std::vector<std::string>& ExportNamingNames();
// InputError located at `where` (e.g. "--names") for any other name, listing the known ones.
ExportNaming ParseExportNaming(const std::string& name, const std::string& where);

// One URDF joint: fixed, or turning about `axis` (in the child link's frame).
struct LinkJoint {
  std::string name;
  std::string parent_link;
  std::string child_link;
  bool movable = false;
  Pose T_parent_child = Pose::Identity();  // at joint value 0 (mm)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  std::optional<NamedJointLimit> limit;  // movable without one: continuous
  std::string limit_comment;             // where the limit comes from, when that needs saying
};

struct RobotLinks {
  std::string base_link;                     // the link that hangs from the world
  std::string base_joint;                    // that fixed joint's name
  Pose T_base_link_base = Pose::Identity();  // cellmetry's base frame in base_link
  std::vector<LinkJoint> joints;             // each parent link before its children
  std::string flange_link;                   // at cellmetry's flange frame: tools hang here
};

// Every link and joint of `robot` (refused as robot_chain.h says for a model that is no chain;
// `ur` also for one that has not six joints).
RobotLinks CalibratedRobotLinks(const CalibratedCell& cell, const CalibratedRobot& robot,
                                ExportNaming naming);
// Only base_link, base_joint, T_base_link_base and flange_link: what tf needs, for any robot
// (a delta arm keeps cellmetry's names; `ur` is refused for it as above).
RobotLinks RobotEnds(const CalibratedCell& cell, const CalibratedRobot& robot, ExportNaming naming);

}  // namespace cellmetry
