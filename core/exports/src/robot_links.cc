// A calibrated robot's links and joints under the names an export asks for (robot_links.h).
#include "cellmetry/exports/robot_links.h"

#include "cellmetry/basics/error.h"
#include "cellmetry/exports/robot_chain.h"
#include "chain_links.h"

namespace cellmetry {
namespace {

// The model's own links and joints, as its description has them.
RobotLinks OwnLinks(const NamedChain& chain, bool with_joints) {
  RobotLinks links;
  links.base_link = chain.base_link;
  links.base_joint = chain.base_link + "_joint";
  links.flange_link = chain.tip_link;
  if (!with_joints) return links;
  for (const NamedJoint& named : chain.joints) {
    LinkJoint joint;
    joint.name = named.name;
    joint.parent_link = named.parent_link;
    joint.child_link = named.child_link;
    joint.movable = named.movable;
    joint.T_parent_child = named.T_parent_child;
    joint.axis = named.axis;
    joint.limit = named.limit;
    links.joints.push_back(joint);
  }
  return links;
}

}  // namespace

const std::vector<std::string>& ExportNamingNames() {
  static const std::vector<std::string> names = {"model", "ur"};
  return names;
}

ExportNaming ParseExportNaming(const std::string& name, const std::string& where) {
  const auto& names = ExportNamingNames();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<ExportNaming>(i);
  }
  throw InputError({where, 0, 0}, "unknown naming '" + name + "'",
                   "Give model (the robot model's own names, else cellmetry's) or ur "
                   "(ur_description's)");
}

RobotLinks CalibratedRobotLinks(const CalibratedCell& cell, const CalibratedRobot& robot,
                                ExportNaming naming) {
  if (naming == ExportNaming::kUr) CheckUrArm(cell, robot);
  const SerialChain chain = CalibratedChain(cell, robot, "a URDF");
  if (naming == ExportNaming::kUr) return UrLinks(robot, &chain);
  NamedChain named;
  if (CalibratedNamedChain(robot, &named)) return OwnLinks(named, true);
  return CellmetryLinks(robot, &chain);
}

RobotLinks RobotEnds(const CalibratedCell& cell, const CalibratedRobot& robot,
                     ExportNaming naming) {
  if (naming == ExportNaming::kUr) {
    CheckUrArm(cell, robot);
    return UrLinks(robot, nullptr);
  }
  NamedChain named;
  if (robot.model->AsNamedChain(robot.values.data(), &named)) return OwnLinks(named, false);
  return CellmetryLinks(robot, nullptr);
}

}  // namespace cellmetry
