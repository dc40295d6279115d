// A calibrated chain under cellmetry's own names (chain_links.h, ros_names.h).
#include "chain_links.h"

#include "cellmetry/exports/ros_names.h"

namespace cellmetry {

LinkJoint ChainJoint(const CalibratedRobot& robot, const SerialChain& chain, size_t index,
                     const std::string& name, const std::string& parent_link,
                     const std::string& child_link) {
  LinkJoint joint;
  joint.name = name;
  joint.parent_link = parent_link;
  joint.child_link = child_link;
  joint.movable = true;
  joint.T_parent_child = chain.T_parent_joint[index];
  const RobotLimits& limits = robot.model->limits();
  if (index < limits.joint_min_rad.size() && index < limits.joint_max_rad.size()) {
    joint.limit = NamedJointLimit{limits.joint_min_rad[index], limits.joint_max_rad[index], 0, 0};
    joint.limit_comment =
        "limits from the robot config; effort and velocity unknown to "
        "cellmetry: set the robot's own";
  }
  return joint;
}

RobotLinks CellmetryLinks(const CalibratedRobot& robot, const SerialChain* chain) {
  RobotLinks links;
  const std::string prefix = RosFrameName(robot.name);
  links.base_link = RosFrameName(robot.name + ".base");
  links.base_joint = links.base_link + "_joint";
  links.flange_link = RosFrameName(robot.name + ".flange");
  if (!chain) return links;
  std::string parent = links.base_link;
  for (size_t i = 0; i < chain->T_parent_joint.size(); ++i) {
    const std::string index = std::to_string(i + 1);
    links.joints.push_back(
        ChainJoint(robot, *chain, i, prefix + "_joint" + index, parent, prefix + "_link" + index));
    parent = prefix + "_link" + index;
  }
  LinkJoint flange;
  flange.name = links.flange_link + "_joint";
  flange.parent_link = parent;
  flange.child_link = links.flange_link;
  flange.T_parent_child = chain->T_last_joint_flange;
  links.joints.push_back(flange);
  return links;
}

}  // namespace cellmetry
