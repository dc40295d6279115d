// The frame the delta effects share (platform_tilt.h, ball_joint_clearance.h): a flange-stage
// effect on some arms of a parallel robot, one parameter per arm, that reads the arms' links
// (RobotModel::ParallelLinks, through EffectContext::links).
#pragma once

#include <vector>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

template <typename Derived>
class ParallelLinkEffect : public EffectFromTemplate<Derived> {
 public:
  ParallelLinkEffect(std::vector<int> arms, std::vector<Parameter> parameters)
      : arms_(std::move(arms)), parameters_(std::move(parameters)) {}

  EffectStage stage() const override { return EffectStage::kFlange; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  EffectNeeds needs() const override {
    EffectNeeds n;
    n.parallel_links = true;
    return n;
  }

 protected:
  std::vector<int> arms_;  // 0-based
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
