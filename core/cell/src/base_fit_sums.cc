// The rigid fit of a robot's base onto world points, in sums (base_fit_sums.h).
#include "base_fit_sums.h"

#include "cellmetry/basics/rigid_fit.h"

namespace cellmetry {

std::vector<size_t> FlangeRunStarts(const std::vector<RobotPoint>& points) {
  std::vector<size_t> starts;
  for (size_t i = 0; i < points.size(); ++i) {
    const RobotPoint* previous = i > 0 ? &points[i - 1] : nullptr;
    if (!previous || points[i].tool != previous->tool ||
        points[i].T_base_flange.R != previous->T_base_flange.R ||
        points[i].T_base_flange.t != previous->T_base_flange.t) {
      starts.push_back(i);
    }
  }
  starts.push_back(points.size());
  return starts;
}

BaseFitSums::BaseFitSums(const std::vector<RobotPoint>& points, int num_tools) {
  ToolSums zero;
  zero.world_axis.fill(Eigen::Matrix3d::Zero());
  zero.axis_offset.fill(Eigen::Matrix3d::Zero());
  for (auto& row : zero.axis_axis) row.fill(Eigen::Matrix3d::Zero());
  tools_.assign(static_cast<size_t>(num_tools), zero);
  count_ = static_cast<double>(points.size());
  if (points.size() < 3) return;
  Eigen::Matrix3d world_scatter = Eigen::Matrix3d::Zero();
  for (const RobotPoint& p : points) {
    world_mean_ += p.p_world / count_;
    offset_mean_ += p.T_base_flange.t / count_;
  }
  const std::vector<size_t> starts = FlangeRunStarts(points);
  for (size_t run = 0; run + 1 < starts.size(); ++run) {
    Eigen::Vector3d world_sum = Eigen::Vector3d::Zero();  // sum of the run's w~_i
    for (size_t i = starts[run]; i < starts[run + 1]; ++i) {
      const Eigen::Vector3d w = points[i].p_world - world_mean_;
      world_scatter += w * w.transpose();
      world_sum += w;
    }
    const double n = static_cast<double>(starts[run + 1] - starts[run]);
    const RobotPoint& p = points[starts[run]];
    const Eigen::Vector3d t = p.T_base_flange.t - offset_mean_;
    const Eigen::Matrix3d& R = p.T_base_flange.R;
    world_offset_ += world_sum * t.transpose();
    offset_offset_ += n * t * t.transpose();
    ToolSums& sums = tools_[static_cast<size_t>(p.tool)];
    sums.rotations += n * R;
    for (int k = 0; k < 3; ++k) {
      sums.world_axis[k] += world_sum * R.col(k).transpose();
      sums.axis_offset[k] += n * R.col(k) * t.transpose();
      for (int l = 0; l < 3; ++l) sums.axis_axis[k][l] += n * R.col(k) * R.col(l).transpose();
    }
  }
  usable_ =
      world_mean_.allFinite() && world_scatter.allFinite() && ScatterSpansAPlane(world_scatter);
}

std::optional<Pose> BaseFitSums::Fit(const std::vector<Eigen::Vector3d>& tool_t) const {
  if (!usable_) return std::nullopt;
  // With g_i = R_i t_tool + t~_i (a flange-side point less t_mean): sum g_i, sum w~_i g_i^T
  // and sum g_i g_i^T.
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cross = world_offset_;
  Eigen::Matrix3d second = offset_offset_;
  for (size_t t = 0; t < tools_.size(); ++t) {
    const ToolSums& sums = tools_[t];
    const Eigen::Vector3d& s = tool_t[t];
    sum += sums.rotations * s;
    for (int k = 0; k < 3; ++k) {
      cross += s[k] * sums.world_axis[k];
      second += s[k] * (sums.axis_offset[k] + sums.axis_offset[k].transpose());
      for (int l = 0; l < 3; ++l) second += s[k] * s[l] * sums.axis_axis[k][l];
    }
  }
  const Eigen::Vector3d mean = sum / count_;
  const Eigen::Matrix3d scatter = second - count_ * mean * mean.transpose();
  if (!cross.allFinite() || !scatter.allFinite() || !ScatterSpansAPlane(scatter)) {
    return std::nullopt;
  }
  Pose T_world_base;
  T_world_base.R = RotationOfCrossCovariance(cross / count_);
  T_world_base.t = world_mean_ - T_world_base.R * (mean + offset_mean_);
  return T_world_base;
}

}  // namespace cellmetry
