// A calibrated six-joint arm as Universal Robots' kinematics YAML (ur_kinematics_export.h).
#include "cellmetry/exports/ur_kinematics_export.h"

#include <cinttypes>
#include <cstdio>
#include <sstream>

#include "cellmetry/basics/error.h"
#include "cellmetry/exports/export_header.h"
#include "cellmetry/exports/robot_chain.h"
#include "cellmetry/exports/roll_pitch_yaw.h"
#include "cellmetry/formats/exact_number.h"

namespace cellmetry {
namespace {

// "xyz = (x, y, z) m, rpy = (r, p, y) rad" of a pose in mm, for comments.
std::string XyzRpyText(const Pose& T) {
  const RollPitchYawAngles a = RollPitchYaw(T.R);
  const Eigen::Vector3d m = T.t / 1000.0;
  return "xyz=\"" + ExactNumber(m.x()) + " " + ExactNumber(m.y()) + " " + ExactNumber(m.z()) +
         "\" rpy=\"" + ExactNumber(a.roll) + " " + ExactNumber(a.pitch) + " " + ExactNumber(a.yaw) +
         "\"";
}

// FNV-1a, 64 bit: a stable name for these numbers.
std::string Hash(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (const unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char out[32];
  std::snprintf(out, sizeof out, "%016" PRIx64, h);
  return out;
}

std::vector<std::string> Comment(const CalibratedCell& cell, const CalibratedRobot& robot,
                                 const SerialChain& chain) {
  std::vector<std::string> lines = ExportHeader(cell, "ur", &robot);
  lines.push_back("");
  lines.push_back(
      "Universal Robots' kinematics file for ur_description (kinematics_params_file:="
      "this file); metres, radians; section i is joint i's URDF origin, the joint's "
      "zero offset folded in, so joint values are the controller's readings.");
  lines.push_back(
      "hash: the UR driver compares it with the controller's own calibration and "
      "logs a mismatch; expected, since this is cellmetry's calibration.");
  if (const CalibratedFrame* base = FindFrame(cell, robot.name + ".base")) {
    // ur_description: base_link -> base is a turn by pi about z, and `base` is the robot's Base.
    const Pose T_world_base_link = base->T_parent_frame * TurnAboutZ(M_PI);
    lines.push_back(
        "The base in the world, as the <origin> of ur_description's base_joint "
        "(parent -> base_link): " +
        XyzRpyText(T_world_base_link));
    lines.push_back("  " + FrameSigmaText(*base));
  }
  for (const auto& frame : cell.frames) {
    if (frame.parent != robot.name + ".flange") continue;
    lines.push_back("Tool '" + frame.name + "' on tool0: " + XyzRpyText(frame.T_parent_frame));
    lines.push_back("  " + FrameSigmaText(frame));
  }
  const std::vector<std::string> left_out = LeftOut(cell, robot, chain.not_expressible);
  lines.push_back("Not in this file: sigma and correlations (result.json)" +
                  std::string(left_out.empty() ? "." : "; and"));
  for (const auto& line : left_out) lines.push_back("  " + line);
  if (!robot.fitted.empty()) {
    lines.push_back("Fitted model parameters (" + robot.model_type + "):");
    for (const auto& p : robot.fitted) lines.push_back("  " + p.name + " = " + ValueWithSigma(p));
  }
  return lines;
}

// The flange offset along the last axis, or false when it is anything else.
bool OnLastAxis(const Pose& T_last_joint_flange) {
  const Eigen::Vector3d z = T_last_joint_flange.R.col(2);
  return std::abs(z.z() - 1.0) < 1e-12 && std::abs(T_last_joint_flange.t.x()) < 1e-9 &&
         std::abs(T_last_joint_flange.t.y()) < 1e-9;
}

}  // namespace

std::string UrKinematicsExport(const CalibratedCell& cell, const CalibratedRobot& robot) {
  SerialChain chain = CalibratedChain(cell, robot, "Universal Robots' kinematics file");
  if (chain.T_parent_joint.size() != 6) {
    throw InputError({cell.json_path, 0, 0},
                     "robot '" + robot.name + "' has " +
                         std::to_string(chain.T_parent_joint.size()) +
                         " joints; Universal Robots' "
                         "kinematics file describes six",
                     "Export it with --format urdf");
  }
  if (!OnLastAxis(chain.T_last_joint_flange)) {
    throw InputError({cell.json_path, 0, 0},
                     "the flange of robot '" + robot.name +
                         "' is not "
                         "on its last joint's axis, where ur_description puts tool0",
                     "Export it with --format urdf");
  }
  // A turn about and a shift along the last axis commute with the joint: fold them into wrist_3.
  chain.T_parent_joint[5] = chain.T_parent_joint[5] * chain.T_last_joint_flange;
  std::ostringstream body;
  body << "kinematics:\n";
  for (int i = 0; i < 6; ++i) {
    const Pose& T = chain.T_parent_joint[i];
    const RollPitchYawAngles a = RollPitchYaw(T.R);
    const Eigen::Vector3d m = T.t / 1000.0;
    body << "  " << kUrKinematicsSections[i] << ":\n"
         << "    x: " << ExactNumber(m.x()) << "\n    y: " << ExactNumber(m.y())
         << "\n    z: " << ExactNumber(m.z()) << "\n    roll: " << ExactNumber(a.roll)
         << "\n    pitch: " << ExactNumber(a.pitch) << "\n    yaw: " << ExactNumber(a.yaw) << "\n";
  }
  const std::string numbers = body.str();
  return CommentLines(Comment(cell, robot, chain), "# ") + numbers + "  hash: calib_cellmetry_" +
         Hash(numbers) + "\n";
}

}  // namespace cellmetry
