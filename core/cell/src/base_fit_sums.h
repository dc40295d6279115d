// The rigid fit of a robot's base onto world points, in sums (internal to the cell layer; the
// closed-form start, workcell_initial.cc, calls it once per round of its alternation).
//
// The start alternates two least-squares steps until they agree: the base pose as the rigid fit
// (Umeyama 1991, without scale) of the flange-side points T_base_flange_i * t_tool onto the
// measured world points p_i, then the base and tool translations for the base rotation found.
// The flange-side points are linear in the tool translations, so everything the fit reads of
// them -- their centroid, their cross-covariance with the world points, their scatter (whether
// they span a plane) -- is a fixed combination of sums over the points, quadratic at most in
// t_tool. Summed once, a round costs a 3 x 3 SVD whatever the number of points, where a pass
// over every point per round was a tenth of exp_a's identification. The sums of flange terms are
// taken once per run of points at one flange pose (FlangeRunStarts), weighted by its count.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

// One carried-target measurement in the world frame (a placed camera's view of it).
struct RobotPoint {
  Pose T_base_flange;
  Eigen::Vector3d p_world;
  Eigen::Matrix3d R_world_target;
  int tool = 0;  // index in the robot's tools
};

// Where each run of consecutive points at one flange pose and tool starts, then the end
// (points.size()). A pose's repeated captures and a capture's cameras follow each other at the
// same joints, so their flange pose is the same to the bit (WorldPoints runs the chain once for
// them): what depends on the flange alone is the same for the whole run (exp_a: 7,500 points in
// 250 runs).
std::vector<size_t> FlangeRunStarts(const std::vector<RobotPoint>& points);

class BaseFitSums {
 public:
  BaseFitSums(const std::vector<RobotPoint>& points, int num_tools);

  // T_world_base minimising sum_i |p_i - T * (T_base_flange_i * tool_t[tool_i])|^2, as
  // FitRigidTransform gives it for those points; std::nullopt where fewer than 3 points,
  // either point set on one line, or a value not finite.
  std::optional<Pose> Fit(const std::vector<Eigen::Vector3d>& tool_t) const;

 private:
  // Sums over one tool's points, with R_i = R_base_flange_i, t~_i = t_base_flange_i - t_mean and
  // w~_i = p_i - p_mean; a flange-side point is R_i t_tool + t~_i + t_mean.
  struct ToolSums {
    Eigen::Matrix3d rotations = Eigen::Matrix3d::Zero();      // sum R_i
    std::array<Eigen::Matrix3d, 3> world_axis;                // k: sum w~_i (R_i e_k)^T
    std::array<std::array<Eigen::Matrix3d, 3>, 3> axis_axis;  // k, l: sum R_i e_k (R_i e_l)^T
    std::array<Eigen::Matrix3d, 3> axis_offset;               // k: sum R_i e_k t~_i^T
  };
  std::vector<ToolSums> tools_;
  double count_ = 0.0;
  Eigen::Vector3d world_mean_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d offset_mean_ = Eigen::Vector3d::Zero();    // t_mean
  Eigen::Matrix3d world_offset_ = Eigen::Matrix3d::Zero();   // sum w~_i t~_i^T
  Eigen::Matrix3d offset_offset_ = Eigen::Matrix3d::Zero();  // sum t~_i t~_i^T
  bool usable_ = false;  // at least 3 finite world points, not on one line
};

}  // namespace cellmetry
