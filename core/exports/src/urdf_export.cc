// A calibrated serial arm as URDF text (urdf_export.h).
#include "cellmetry/exports/urdf_export.h"

#include <sstream>

#include "cellmetry/exports/export_header.h"
#include "cellmetry/exports/robot_chain.h"
#include "cellmetry/exports/robot_links.h"
#include "cellmetry/exports/ros_names.h"
#include "cellmetry/exports/xml_text.h"
#include "cellmetry/formats/exact_number.h"

namespace cellmetry {
namespace {

void Link(const std::string& name, std::ostream& out) {
  out << "  <link name=\"" << EscapeXml(name) << "\"/>\n";
}

void FixedJoint(const std::string& name, const std::string& parent, const std::string& child,
                const Pose& T_parent_child, std::ostream& out) {
  out << "  <joint name=\"" << EscapeXml(name) << "\" type=\"fixed\">\n"
      << "    <parent link=\"" << EscapeXml(parent) << "\"/>\n"
      << "    <child link=\"" << EscapeXml(child) << "\"/>\n"
      << "    " << UrdfOrigin(T_parent_child) << "\n"
      << "  </joint>\n";
}

std::vector<std::string> Comment(const CalibratedCell& cell, const CalibratedRobot& robot,
                                 const SerialChain& chain) {
  std::vector<std::string> lines = ExportHeader(cell, "urdf", &robot);
  lines.push_back("");
  lines.push_back(
      "Metres, radians. Each movable joint turns about its axis by the "
      "controller's reading; its origin is the calibrated geometry with the joint's "
      "zero offset folded in (a rotation about that axis before the joint), so "
      "joint values are the readings as the controller reports them.");
  lines.push_back(
      "Kinematics only: no inertia, visuals, collision shapes or effort and "
      "velocity limits (cellmetry does not measure them).");
  const std::vector<std::string> left_out = LeftOut(cell, robot, chain.not_expressible);
  lines.push_back(
      "Not in this file (a URDF cannot hold it): the sigma of every number below, "
      "and their correlations (result.json)" +
      std::string(left_out.empty() ? "." : "; and"));
  for (const auto& line : left_out) lines.push_back("  " + line);
  if (!robot.fitted.empty()) {
    lines.push_back("Fitted model parameters (" + robot.model_type + "):");
    for (const auto& p : robot.fitted) lines.push_back("  " + p.name + " = " + ValueWithSigma(p));
  }
  return lines;
}

// One joint of the robot, as URDF writes it.
void RobotJoint(const LinkJoint& joint, std::ostream& out) {
  if (!joint.movable) {
    FixedJoint(joint.name, joint.parent_link, joint.child_link, joint.T_parent_child, out);
    return;
  }
  const Eigen::Vector3d& a = joint.axis;
  out << "  <joint name=\"" << EscapeXml(joint.name) << "\" type=\""
      << (joint.limit ? "revolute" : "continuous") << "\">\n"
      << "    <parent link=\"" << EscapeXml(joint.parent_link) << "\"/>\n"
      << "    <child link=\"" << EscapeXml(joint.child_link) << "\"/>\n"
      << "    " << UrdfOrigin(joint.T_parent_child) << "\n"
      << "    <axis xyz=\"" << ExactNumber(a.x()) << " " << ExactNumber(a.y()) << " "
      << ExactNumber(a.z()) << "\"/>\n";
  if (joint.limit) {
    if (!joint.limit_comment.empty()) out << "    <!-- " << joint.limit_comment << " -->\n";
    out << "    <limit lower=\"" << ExactNumber(joint.limit->lower_rad) << "\" upper=\""
        << ExactNumber(joint.limit->upper_rad) << "\" effort=\"" << ExactNumber(joint.limit->effort)
        << "\" velocity=\"" << ExactNumber(joint.limit->velocity) << "\"/>\n";
  }
  out << "  </joint>\n";
}

}  // namespace

std::string UrdfExport(const CalibratedCell& cell, const CalibratedRobot& robot,
                       ExportNaming naming) {
  const RobotLinks links = CalibratedRobotLinks(cell, robot, naming);
  const SerialChain chain = CalibratedChain(cell, robot, "a URDF");
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n" << XmlComment(Comment(cell, robot, chain), "");
  out << "<robot name=\"" << EscapeXml(RosFrameName(robot.name)) << "\">\n";
  Link("world", out);
  Link(links.base_link, out);
  const CalibratedFrame* base_frame = FindFrame(cell, robot.name + ".base");
  if (base_frame) out << XmlComment({"T_world_base: " + FrameSigmaText(*base_frame)}, "  ");
  const Pose T_world_base = base_frame ? base_frame->T_parent_frame : Pose::Identity();
  FixedJoint(links.base_joint, "world", links.base_link,
             T_world_base * links.T_base_link_base.inverse(), out);
  for (const LinkJoint& joint : links.joints) {
    Link(joint.child_link, out);
    RobotJoint(joint, out);
  }
  for (const auto& frame : cell.frames) {
    if (frame.parent != robot.name + ".flange") continue;
    const std::string tool = RosFrameName(frame.name);
    Link(tool, out);
    out << XmlComment({"T_flange_" + frame.name + ": " + FrameSigmaText(frame)}, "  ");
    FixedJoint(tool + "_joint", links.flange_link, tool, frame.T_parent_frame, out);
  }
  out << "</robot>\n";
  return out.str();
}

}  // namespace cellmetry
