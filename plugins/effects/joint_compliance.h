// JointCompliance (`joint_compliance`): joints that give under the gravity load they carry.
//
//   dq_i = c_i * tau_g,i(q)        c_i in rad/(N m), parameter "j<i>.compliance"
//
// tau_g,i is the gravity torque about joint i (GravityTorques in effect.h): lumped link masses
// from the config (`link_masses_kg`, one per joint; default 1 kg each) at the links' midpoints,
// the sample's payload (samples.csv `payload`) at the flange, gravity along -z of the base unless
// the recording's context says otherwise. A model without joint frames (a delta, whose motors
// do not carry each other) takes the links' masses as hanging on the flange with the payload,
// through the flange Jacobian (FlangeLoadTorques). The torque is taken at the nominal geometry:
// the geometry's own corrections change it by parts per thousand.
#pragma once

#include <vector>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class JointCompliance : public EffectFromTemplate<JointCompliance> {
 public:
  JointCompliance(std::vector<int> joints, std::vector<double> link_masses_kg);

  EffectStage stage() const override { return EffectStage::kJoint; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  EffectNeeds needs() const override { return {.joint_frames = true}; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* dq) const {
    const std::vector<double> torque = ContextGravityTorques(context, link_masses_kg_);
    if (torque.empty()) return;
    for (size_t k = 0; k < joints_.size(); ++k) dq[joints_[k]] += params[k] * torque[joints_[k]];
  }

 private:
  std::vector<int> joints_;
  std::vector<double> link_masses_kg_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
