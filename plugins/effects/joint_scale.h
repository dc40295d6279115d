// JointScale (`joint_scale`): a gear ratio or encoder resolution slightly off, so the joint
// turns by (1 + s_i) times what its reading says:
//
//   dq_i = s_i * q_i          s_i unitless, parameter "j<i>.scale"
#pragma once

#include <vector>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class JointScale : public EffectFromTemplate<JointScale> {
 public:
  explicit JointScale(std::vector<int> joints);

  EffectStage stage() const override { return EffectStage::kJoint; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* dq) const {
    for (size_t k = 0; k < joints_.size(); ++k) dq[joints_[k]] += params[k] * context.q[joints_[k]];
  }

 private:
  std::vector<int> joints_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
