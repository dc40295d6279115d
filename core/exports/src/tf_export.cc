// Every identified frame as ROS 2 static transforms (tf_export.h).
#include "cellmetry/exports/tf_export.h"

#include <Eigen/Geometry>
#include <cstdio>
#include <map>
#include <sstream>

#include "cellmetry/exports/export_header.h"
#include "cellmetry/exports/relative_pose.h"
#include "cellmetry/exports/robot_links.h"
#include "cellmetry/exports/ros_names.h"
#include "cellmetry/exports/xml_text.h"
#include "cellmetry/formats/exact_number.h"
#include "cellmetry/model/frame_block.h"

namespace cellmetry {
namespace {

std::string NodeName(const std::string& child) {
  std::string name = "cellmetry_" + child;
  for (char& c : name) {
    if (c == '/') c = '_';
  }
  return name;
}

// The pose's translation in metres and its unit quaternion with qw >= 0.
struct RosPose {
  Eigen::Vector3d m;
  Eigen::Quaterniond q;
};

RosPose ToRos(const Pose& T) {
  RosPose p{T.t / 1000.0, Eigen::Quaterniond(T.R)};
  p.q.normalize();
  if (p.q.w() < 0) p.q.coeffs() = -p.q.coeffs();
  return p;
}

// "--x .. --y .. --z .. --qx .. --qy .. --qz .. --qw .." of a pose in mm.
std::string PoseArguments(const Pose& T) {
  const RosPose p = ToRos(T);
  return "--x " + ExactNumber(p.m.x()) + " --y " + ExactNumber(p.m.y()) + " --z " +
         ExactNumber(p.m.z()) + " --qx " + ExactNumber(p.q.x()) + " --qy " + ExactNumber(p.q.y()) +
         " --qz " + ExactNumber(p.q.z()) + " --qw " + ExactNumber(p.q.w());
}

// "xyz (m) = (..), quaternion (x y z w) = (..)" for comments (which cannot hold "--").
std::string PoseText(const Pose& T) {
  const RosPose p = ToRos(T);
  return "xyz (m) = (" + ExactNumber(p.m.x()) + ", " + ExactNumber(p.m.y()) + ", " +
         ExactNumber(p.m.z()) + "), quaternion (x y z w) = (" + ExactNumber(p.q.x()) + ", " +
         ExactNumber(p.q.y()) + ", " + ExactNumber(p.q.z()) + ", " + ExactNumber(p.q.w()) + ")";
}

// The 6 x 6 covariance of a frame's (x y z rx ry rz) from the result's, zero where held.
Eigen::Matrix<double, 12, 12> PairCovariance(const ParameterCovariance& c, const std::string& a,
                                             const std::string& b) {
  Eigen::Matrix<double, 12, 12> out = Eigen::Matrix<double, 12, 12>::Zero();
  std::array<int, 12> index;
  for (int i = 0; i < 12; ++i) {
    index[i] = c.Find((i < 6 ? a : b) + "." + kFrameParameterNames[i % 6]);
  }
  for (int i = 0; i < 12; ++i) {
    for (int k = 0; k < 12; ++k) {
      if (index[i] >= 0 && index[k] >= 0) out(i, k) = c.covariance(index[i], index[k]);
    }
  }
  return out;
}

std::string SigmaText(const Matrix6d& covariance, int offset) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.2g, %.2g, %.2g)", std::sqrt(covariance(offset, offset)),
                std::sqrt(covariance(offset + 1, offset + 1)),
                std::sqrt(covariance(offset + 2, offset + 2)));
  return text;
}

// Each robot's base in every other robot's base, as comment lines.
std::vector<std::string> RobotToRobot(const CalibratedCell& cell) {
  std::vector<std::string> lines;
  for (const auto& a : cell.robots) {
    for (const auto& b : cell.robots) {
      const CalibratedFrame* base_a = FindFrame(cell, a.name + ".base");
      const CalibratedFrame* base_b = FindFrame(cell, b.name + ".base");
      if (a.name == b.name || !base_a || !base_b || base_a->parent != base_b->parent) continue;
      const RelativePose relative =
          PoseInFrame(base_a->T_parent_frame, base_b->T_parent_frame,
                      PairCovariance(cell.covariance, base_a->name, base_b->name));
      lines.push_back(RosFrameName(base_b->name) + " in " + RosFrameName(base_a->name) + ": " +
                      PoseText(relative.T_a_b));
      lines.push_back("  sigma xyz " + SigmaText(relative.covariance, 0) + " mm, rot " +
                      SigmaText(relative.covariance, 3) +
                      " rad (first order, with the bases' "
                      "correlation)");
    }
  }
  return lines;
}

// Each frame's ROS parent, child and transform: a robot's base and flange under the names of its
// URDF export (robot_links.h), where `ur_robot` (if any) is named as ur_description does.
struct RosFrame {
  std::string parent;
  std::string child;
  Pose T_parent_child;
};

std::vector<RosFrame> RosFrames(const CalibratedCell& cell, const std::string& ur_robot) {
  std::map<std::string, std::string> names;      // cellmetry frame -> ROS frame
  std::map<std::string, Pose> T_base_link_base;  // cellmetry base frame -> where it is in its link
  for (const CalibratedRobot& robot : cell.robots) {
    const ExportNaming naming = robot.name == ur_robot ? ExportNaming::kUr : ExportNaming::kModel;
    const RobotLinks ends = RobotEnds(cell, robot, naming);
    names[robot.name + ".base"] = ends.base_link;
    names[robot.name + ".flange"] = ends.flange_link;
    T_base_link_base[robot.name + ".base"] = ends.T_base_link_base;
  }
  const auto ros_name = [&](const std::string& frame) {
    const auto found = names.find(frame);
    return found == names.end() ? RosFrameName(frame) : found->second;
  };
  std::vector<RosFrame> frames;
  for (const auto& frame : cell.frames) {
    Pose T = frame.T_parent_frame;
    const auto base = T_base_link_base.find(frame.name);
    if (base != T_base_link_base.end()) T = T * base->second.inverse();
    frames.push_back({ros_name(frame.parent), ros_name(frame.name), T});
  }
  return frames;
}

}  // namespace

std::string TfLaunchExport(const CalibratedCell& cell, const std::string& ur_robot) {
  std::vector<std::string> header = ExportHeader(cell, "tf", nullptr);
  header.push_back("");
  header.push_back(
      "ROS 2 static transforms of every frame the result identified: "
      "`ros2 launch <this file>`. Metres, unit quaternions.");
  header.push_back(
      "Bases and tools hang from the links of the urdf export with the same "
      "--names (robot_state_publisher moves them): <robot>_base and "
      "<robot>_flange, a urdf robot's own base and tip links, or base_link and "
      "tool0 with --names ur.");
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n" << XmlComment(header, "") << "<launch>\n";
  const std::vector<RosFrame> ros_frames = RosFrames(cell, ur_robot);
  for (size_t i = 0; i < ros_frames.size(); ++i) {
    const RosFrame& frame = ros_frames[i];
    out << XmlComment({FrameSigmaText(cell.frames[i])}, "  ")
        << "  <node pkg=\"tf2_ros\" exec=\"static_transform_publisher\" name=\""
        << EscapeXml(NodeName(frame.child)) << "\"\n        args=\""
        << PoseArguments(frame.T_parent_child) << " --frame-id " << EscapeXml(frame.parent)
        << " --child-frame-id " << EscapeXml(frame.child) << "\"/>\n";
  }
  const std::vector<std::string> relative = RobotToRobot(cell);
  if (!relative.empty()) {
    std::vector<std::string> lines = {
        "Robot to robot (not published: each base already hangs "
        "from the world, and a tf frame has one parent):"};
    lines.insert(lines.end(), relative.begin(), relative.end());
    out << XmlComment(lines, "  ");
  }
  out << "</launch>\n";
  return out.str();
}

}  // namespace cellmetry
