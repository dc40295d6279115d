// TARGETS.csv: what `cellmetry compensate` is asked to reach (docs/formats.md).
//
// A header row, then one target per row; lines starting with '#' are comments. Columns:
//
//   id                          optional text naming the target (default: its line number)
//   x_mm, y_mm, z_mm            the tool's origin in the world frame of the result (mm)
//   rx_rad, ry_rad, rz_rad      optional, with x y z: the tool's rotation in the world as a
//                               rotation vector (axis times angle, rad; R = exp([r]x), the
//                               convention of result.json's rvec_rad). Without them (or with
//                               them empty on a row) only the position is asked for. Only an arm
//                               of six or more joints turns its tool at will: a delta's rows are
//                               positions.
//   q1_rad ... q<n>_rad         a joint target (a row with x y z empty, or no x y z columns):
//                               where the robot config's nominal kinematics puts the tool at
//                               these readings is the target. Beside x y z: the seed, the joint
//                               values near the solution meant (an arm reaches most poses in
//                               several configurations)
//   Each group (x y z; rx ry rz; q1 ... q<n>; approach_j1 ...) is all filled or all empty on a
//   row.
//   payload_kg                  optional, >= 0 (default 0): the load at the flange (compliance)
//   temperature_c, t_s          optional: the arm's temperature (degC) and time since a cold
//                               start (s), for thermal effects that need them
//   approach_j1 ... approach_j<n>  optional, per row all or none: -1, 0 or +1, the direction
//                               each joint moves into the target (backlash). Without them the
//                               direction is the move from the previous row's command, file
//                               order, as a recording's capture order defines it
//
// Every number is checked (finite, in range); a bad cell is an InputError naming
// file:line:column and what to write instead (exit code 2). Unknown columns are refused.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace cellmetry {

struct CompensationTarget {
  enum class Kind { kPose, kPosition, kJoints };
  int line = 0;  // in TARGETS.csv, for messages
  std::string id;
  Kind kind = Kind::kPosition;
  Eigen::Vector3d p_world_tool_mm = Eigen::Vector3d::Zero();   // kPose, kPosition
  Eigen::Matrix3d R_world_tool = Eigen::Matrix3d::Identity();  // kPose
  std::vector<double> q_rad;  // kJoints: the joint target; otherwise the seed (empty: none)
  double payload_kg = 0.0;
  double temperature_c = NAN;
  double time_s = NAN;
  std::vector<int> approach;  // per joint; empty: from the order of the commands
};

// Reads `path` for a robot of `num_joints` joints.
std::vector<CompensationTarget> ReadCompensationTargets(const std::string& path, int num_joints);

}  // namespace cellmetry
