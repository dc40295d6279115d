// A calibrated six-joint arm under ur_description's names and frames (chain_links.h).
//
// ur_description (ur_macro.xacro) builds
//
//   base_link --(Rz(pi))--> base_link_inertia --shoulder_pan_joint--> shoulder_link
//   --shoulder_lift_joint--> upper_arm_link --elbow_joint--> forearm_link --wrist_1_joint-->
//   wrist_1_link --wrist_2_joint--> wrist_2_link --wrist_3_joint--> wrist_3_link
//   --(rpy 0 -pi/2 -pi/2)--> flange --(rpy pi/2 0 pi/2)--> tool0
//   base_link --(Rz(pi))--> base
//
// each joint's origin from its kinematics YAML in the frame of the link before, turning about z.
// base_link_inertia and base are the controller's Base frame, tool0 its tool flange: cellmetry's
// base and flange for the UR configs (configs/robots/ur*.yaml), so the joints' origins are the
// chain's T_parent_joint as the `ur` export writes them (ur_kinematics_export.h). For those
// configs (modified DH rows regrouped from UR's DH table) the chain's joint frames are the link
// frames ur_description puts its meshes in. A flange off the last joint's frame
// (T_last_joint_flange not the identity) goes into wrist_3-flange, so that tool0 stays
// cellmetry's flange.
#include <Eigen/Geometry>

#include "cellmetry/basics/error.h"
#include "chain_links.h"

namespace cellmetry {
namespace {

constexpr const char* kJointNames[6] = {"shoulder_pan_joint", "shoulder_lift_joint",
                                        "elbow_joint",        "wrist_1_joint",
                                        "wrist_2_joint",      "wrist_3_joint"};
constexpr const char* kLinkNames[7] = {"base_link_inertia", "shoulder_link", "upper_arm_link",
                                       "forearm_link",      "wrist_1_link",  "wrist_2_link",
                                       "wrist_3_link"};

Pose Rotation(double roll, double pitch, double yaw) {
  Pose T;
  T.R = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
  return T;
}

LinkJoint Fixed(const std::string& name, const std::string& parent, const std::string& child,
                const Pose& T_parent_child) {
  LinkJoint joint;
  joint.name = name;
  joint.parent_link = parent;
  joint.child_link = child;
  joint.T_parent_child = T_parent_child;
  return joint;
}

}  // namespace

void CheckUrArm(const CalibratedCell& cell, const CalibratedRobot& robot) {
  SerialChain chain;
  const bool serial = robot.model->AsSerialChain(robot.values.data(), &chain);
  if (serial && robot.model->num_joints() == 6) return;
  throw InputError(
      {cell.json_path, 0, 0},
      "--names ur names a six-joint serial arm as ur_description does; robot '" + robot.name +
          "' (model " + robot.model_type + ") is " +
          (serial ? "a chain of " + std::to_string(robot.model->num_joints()) + " joints"
                  : "not a serial chain"),
      "Leave out --names ur (or give --names model)");
}

RobotLinks UrLinks(const CalibratedRobot& robot, const SerialChain* chain) {
  RobotLinks links;
  links.base_link = "base_link";
  links.base_joint = "base_joint";
  links.T_base_link_base = Rotation(0, 0, M_PI);
  links.flange_link = "tool0";
  if (!chain) return links;
  links.joints.push_back(
      Fixed("base_link-base_link_inertia", "base_link", "base_link_inertia", Rotation(0, 0, M_PI)));
  links.joints.push_back(
      Fixed("base_link-base_fixed_joint", "base_link", "base", Rotation(0, 0, M_PI)));
  for (size_t i = 0; i < 6; ++i) {
    links.joints.push_back(
        ChainJoint(robot, *chain, i, kJointNames[i], kLinkNames[i], kLinkNames[i + 1]));
  }
  const Pose T_flange_tool0 = Rotation(M_PI / 2, 0, M_PI / 2);
  links.joints.push_back(Fixed("wrist_3-flange", "wrist_3_link", "flange",
                               chain->T_last_joint_flange * T_flange_tool0.inverse()));
  links.joints.push_back(Fixed("flange-tool0", "flange", "tool0", T_flange_tool0));
  return links;
}

}  // namespace cellmetry
