// Backlash (`backlash`): play in a joint's gear train. The joint lags its reading by half the
// play, on the side it came from:
//
//   dq_i = -b_i / 2 * approach_i   b_i in rad, parameter "j<i>.backlash"
//
// approach_i is the sign of joint i's last move into the pose, in capture order
// (EffectContext); a joint that has not moved yet has none and no correction. A recording whose
// joints always approach from one side cannot tell backlash from a joint offset.
#pragma once

#include <vector>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class Backlash : public EffectFromTemplate<Backlash> {
 public:
  explicit Backlash(std::vector<int> joints);

  EffectStage stage() const override { return EffectStage::kJoint; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  EffectNeeds needs() const override { return {.approach = true}; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* dq) const {
    if (!context.approach) return;
    for (size_t k = 0; k < joints_.size(); ++k) {
      dq[joints_[k]] -= 0.5 * params[k] * double(context.approach[joints_[k]]);
    }
  }

 private:
  std::vector<int> joints_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
