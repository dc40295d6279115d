// JointCoupling (`joint_coupling`): joints turning with another joint's reading. In a wrist whose
// motors sit behind it (a Staubli's joints 5 and 6, many others' 4, 5 and 6) a driven joint's
// shaft runs through the joint before it, so turning that joint turns the driven one too; the
// controller takes the ratio out, and what it takes out wrongly remains:
//
//   dq_i = k_i * q_from        k_i unitless (rad per rad), parameter "j<i>.coupling_j<from>"
//
// `joints: [6]` names the driven joints, `from: 5` the driving one (1-based).
#pragma once

#include <vector>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class JointCoupling : public EffectFromTemplate<JointCoupling> {
 public:
  JointCoupling(std::vector<int> driven_joints, int driving_joint);

  EffectStage stage() const override { return EffectStage::kJoint; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* dq) const {
    for (size_t k = 0; k < driven_joints_.size(); ++k) {
      dq[driven_joints_[k]] += params[k] * context.q[driving_joint_];
    }
  }

 private:
  std::vector<int> driven_joints_;  // 0-based
  int driving_joint_;               // 0-based
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
