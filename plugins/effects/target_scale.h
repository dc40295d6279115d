// TargetScale (`target_scale`): a target printed at another size than its pose estimator was
// told. PnP finds the pose of a board k times its stated size at k times the distance along the
// same ray, so every coordinate of the measured position scales, in every camera that sees it:
//
//   p' = p (1 + s)        per target: "<target>.scale" (unitless)
//
// A printer's 1 % is 1 % of the distance: 10 mm at a metre. It differs from a camera's depth
// error (depth_bias) by following the target, not the camera.
//
// `targets: [tool, world]` names the targets (required). `shared: true`: one scale for all of
// them, "scale" (boards printed on one printer at one setting: what scales one scales all).
#pragma once

#include <string>
#include <vector>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class TargetScale : public EffectFromTemplate<TargetScale> {
 public:
  TargetScale(std::vector<std::string> targets, bool shared);

  EffectStage stage() const override { return EffectStage::kMeasurement; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* p_cam) const {
    for (size_t t = 0; t < targets_.size(); ++t) {
      if (targets_[t] != context.target) continue;
      const T& scale = params[shared_ ? 0 : t];
      for (int i = 0; i < 3; ++i) p_cam[i] *= T(1.0) + scale;
    }
  }

 private:
  std::vector<std::string> targets_;
  bool shared_ = false;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
