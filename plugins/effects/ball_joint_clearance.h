// BallJointClearance (`ball_joint_clearance`): play in a delta arm's ball joints, held closed by
// preload springs, so each rod pair gives along its length in proportion to the load it carries.
// The platform's weight (and payload) hangs from the three rod pairs: with u_i the unit rod
// directions (platform toward elbow, RobotModel::ParallelLinks) and g the gravity direction,
// the tensions' shares of the weight solve
//
//   sum_i s_i u_i = -g / |g|                 (statics of the platform)
//
// and rod pair i lengthens by c_i s_i, which moves the platform by dp with u_i . dp = -c_i s_i
// (a longer rod holds the platform further from its elbow). c_i (mm, "arm<i>.clearance") is
// the play taken up at a share of 1. The shares change over the workspace as the rods turn,
// which tells clearance from a rod length error; where they hardly change (a small workspace),
// the geometry absorbs it. Acts on delta arms only (needs parallel links).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "parallel_link_effect.h"

namespace cellmetry::effects {

class BallJointClearance : public ParallelLinkEffect<BallJointClearance> {
 public:
  explicit BallJointClearance(std::vector<int> arms);

  std::string Describe(const std::vector<double>& params) const override;

  // values: p_base_flange[3] (moved), then the rotation (unchanged).
  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* values) const {
    Eigen::Matrix3d move_per_clearance;
    if (!MovePerClearance(context, &move_per_clearance)) return;
    for (size_t k = 0; k < arms_.size(); ++k) {
      for (int a = 0; a < 3; ++a) values[a] += move_per_clearance(a, arms_[k]) * params[k];
    }
  }

 private:
  // Column i: the platform's move (mm) per mm of arm i's clearance; false without three links.
  static bool MovePerClearance(const EffectContext& context, Eigen::Matrix3d* move_per_clearance);
};

}  // namespace cellmetry::effects
