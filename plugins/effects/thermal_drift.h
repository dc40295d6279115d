// ThermalDrift (`thermal_drift`): the arm's links grow as it warms, which scales the flange's
// distance from the base (every length of the chain alike):
//
//   by temperature (samples.csv `temperature`):  p' = p (1 + k (T - T_ref))
//        k in 1/degC ("expansion"), T_ref from `reference_c` (default 20)
//   by warm-up time (samples.csv `t`):           p' = p (1 + g (1 - exp(-t / tau)))
//        g unitless ("warmup_growth"), tau from `time_constant_s` (default 1800)
//
// `model: temperature | warmup` (default temperature). Steel grows 1.2e-5 per degC; an
// aluminium arm 2.3e-5: 0.5 m of reach moves 0.1 mm for 10 degC.
#pragma once

#include <cmath>
#include <vector>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class ThermalDrift : public EffectFromTemplate<ThermalDrift> {
 public:
  enum class Model { kTemperature, kWarmup };
  ThermalDrift(Model model, double reference_c, double time_constant_s);

  EffectStage stage() const override { return EffectStage::kFlange; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  EffectNeeds needs() const override {
    EffectNeeds n;
    (model_ == Model::kTemperature ? n.temperature : n.time) = true;
    return n;
  }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* p_base_flange) const {
    const double driver = model_ == Model::kTemperature
                              ? context.temperature_c - reference_c_
                              : 1.0 - std::exp(-context.time_s / time_constant_s_);
    if (!std::isfinite(driver)) return;
    const T scale = T(1.0) + params[0] * driver;
    for (int i = 0; i < 3; ++i) p_base_flange[i] *= scale;
  }

 private:
  Model model_;
  double reference_c_;
  double time_constant_s_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
