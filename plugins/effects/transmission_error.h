// TransmissionError (`transmission_error`): a gear train's angle error that repeats with the
// joint's own rotation (eccentric gears, harmonic-drive flexspline), per harmonic h:
//
//   dq_i = sum_h  s_ih sin(h q_i) + c_ih cos(h q_i)     rad; parameters "j<i>.h<h>.sin/cos"
//
// `harmonics: [1, 2]` by default; give the gear's own harmonics (per joint revolution) to add
// them. Over a small joint range the first harmonic looks like an offset and a scale error,
// which the geometry absorbs: the diagnosis says so.
#pragma once

#include <cmath>
#include <vector>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class TransmissionError : public EffectFromTemplate<TransmissionError> {
 public:
  TransmissionError(std::vector<int> joints, std::vector<int> harmonics);

  EffectStage stage() const override { return EffectStage::kJoint; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* dq) const {
    size_t k = 0;
    for (int joint : joints_) {
      for (int h : harmonics_) {
        const double angle = h * context.q[joint];
        dq[joint] += params[k] * std::sin(angle) + params[k + 1] * std::cos(angle);
        k += 2;
      }
    }
  }

 private:
  std::vector<int> joints_;
  std::vector<int> harmonics_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
