// Backlash (`backlash`): play in a joint's gear train. Where nothing loads the joint, it lags its
// reading by half the play, on the side it came from (`held_by: approach`, the default):
//
//   dq_i = -b_i / 2 * approach_i   b_i in rad, parameter "j<i>.backlash"
//
// approach_i is the sign of joint i's last move into the pose, in capture order
// (EffectContext); a joint that has not moved yet has none and no correction. A recording whose
// joints always approach from one side cannot tell backlash from a joint offset.
//
// Where gravity loads the joint (a shoulder or elbow), its torque holds the output against one
// flank whichever way the joint came (`held_by: gravity`, with the links' masses as
// joint_compliance takes them):
//
//   dq_i = b_i / 2 * tanh(tau_g,i(q) / tau_hold)
//
// where tau_hold (`hold_nm`, default 2 N m) is the torque the joint's friction holds against:
// below it the joint sits inside its play, beyond it against the flank. It gives with gravity as
// a compliance does, but by the same amount at any load beyond tau_hold: poses whose gravity
// torque on the joint differs in size, not only in sign (payloads, outstretched and folded),
// tell the two apart.
#pragma once

#include <cmath>
#include <vector>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class Backlash : public EffectFromTemplate<Backlash> {
 public:
  // Held where the last move left it (empty `link_masses_kg`), or by gravity under those masses.
  Backlash(std::vector<int> joints, std::vector<double> link_masses_kg, double hold_nm = 2.0);

  EffectStage stage() const override { return EffectStage::kJoint; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  EffectNeeds needs() const override {
    return held_by_gravity() ? EffectNeeds{.joint_frames = true} : EffectNeeds{.approach = true};
  }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* dq) const {
    if (held_by_gravity()) {
      const std::vector<double> torque = ContextGravityTorques(context, link_masses_kg_);
      if (torque.empty()) return;
      for (size_t k = 0; k < joints_.size(); ++k) {
        const double tau = torque[joints_[k]];
        dq[joints_[k]] += 0.5 * params[k] * std::tanh(tau / hold_nm_);
      }
      return;
    }
    if (!context.approach) return;
    for (size_t k = 0; k < joints_.size(); ++k) {
      dq[joints_[k]] -= 0.5 * params[k] * double(context.approach[joints_[k]]);
    }
  }

 private:
  bool held_by_gravity() const { return !link_masses_kg_.empty(); }

  std::vector<int> joints_;
  std::vector<double> link_masses_kg_;
  double hold_nm_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
