// A calibrated serial arm as URDF text (urdf_export.h).
#include "cellmetry/exports/urdf_export.h"

#include <sstream>

#include "cellmetry/exports/export_header.h"
#include "cellmetry/exports/robot_chain.h"
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
  lines.push_back("Metres, radians. Joint i turns about the z axis of its frame by the "
                  "controller's reading; its origin is the calibrated geometry with the joint's "
                  "zero offset folded in (a rotation about that axis before the joint), so "
                  "joint values are the readings as the controller reports them.");
  lines.push_back("Kinematics only: no inertia, visuals, collision shapes or effort and "
                  "velocity limits (cellmetry does not measure them).");
  const std::vector<std::string> left_out = LeftOut(cell, robot, chain.not_expressible);
  lines.push_back("Not in this file (a URDF cannot hold it): the sigma of every number below, "
                  "and their correlations (result.json)" +
                  std::string(left_out.empty() ? "." : "; and"));
  for (const auto& line : left_out) lines.push_back("  " + line);
  if (!robot.fitted.empty()) {
    lines.push_back("Fitted model parameters (" + robot.model_type + "):");
    for (const auto& p : robot.fitted) lines.push_back("  " + p.name + " = " + ValueWithSigma(p));
  }
  return lines;
}

}  // namespace

std::string UrdfExport(const CalibratedCell& cell, const CalibratedRobot& robot) {
  const SerialChain chain = CalibratedChain(cell, robot, "a URDF");
  const std::string base = RosFrameName(robot.name + ".base");
  const std::string flange = RosFrameName(robot.name + ".flange");
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n" << XmlComment(Comment(cell, robot, chain), "");
  out << "<robot name=\"" << EscapeXml(RosFrameName(robot.name)) << "\">\n";
  Link("world", out);
  Link(base, out);
  const CalibratedFrame* base_frame = FindFrame(cell, robot.name + ".base");
  if (base_frame) out << XmlComment({"T_world_base: " + FrameSigmaText(*base_frame)}, "  ");
  FixedJoint(base + "_joint", "world", base,
             base_frame ? base_frame->T_parent_frame : Pose::Identity(), out);
  const RobotLimits& limits = robot.model->limits();
  std::string parent = base;
  for (size_t i = 0; i < chain.T_parent_joint.size(); ++i) {
    const std::string index = std::to_string(i + 1);
    const std::string link = RosFrameName(robot.name) + "_link" + index;
    const bool limited = i < limits.joint_min_rad.size() && i < limits.joint_max_rad.size();
    Link(link, out);
    out << "  <joint name=\"" << EscapeXml(RosFrameName(robot.name) + "_joint" + index)
        << "\" type=\"" << (limited ? "revolute" : "continuous") << "\">\n"
        << "    <parent link=\"" << EscapeXml(parent) << "\"/>\n"
        << "    <child link=\"" << EscapeXml(link) << "\"/>\n"
        << "    " << UrdfOrigin(chain.T_parent_joint[i]) << "\n"
        << "    <axis xyz=\"0 0 1\"/>\n";
    if (limited) {
      out << "    <!-- limits from the robot config; effort and velocity unknown to cellmetry: "
             "set the robot's own -->\n"
          << "    <limit lower=\"" << ExactNumber(limits.joint_min_rad[i]) << "\" upper=\""
          << ExactNumber(limits.joint_max_rad[i]) << "\" effort=\"0\" velocity=\"0\"/>\n";
    }
    out << "  </joint>\n";
    parent = link;
  }
  Link(flange, out);
  FixedJoint(flange + "_joint", parent, flange, chain.T_last_joint_flange, out);
  for (const auto& frame : cell.frames) {
    if (frame.parent != robot.name + ".flange") continue;
    const std::string tool = RosFrameName(frame.name);
    Link(tool, out);
    out << XmlComment({"T_flange_" + frame.name + ": " + FrameSigmaText(frame)}, "  ");
    FixedJoint(tool + "_joint", flange, tool, frame.T_parent_frame, out);
  }
  out << "</robot>\n";
  return out.str();
}

}  // namespace cellmetry
