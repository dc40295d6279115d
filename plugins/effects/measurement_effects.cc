// Constructors and descriptions of the effects outside the joints (thermal_drift.h,
// depth_bias.h).
#include "depth_bias.h"
#include "describe.h"
#include "thermal_drift.h"

namespace cellmetry::effects {

ThermalDrift::ThermalDrift(Model model, double reference_c, double time_constant_s)
    : model_(model), reference_c_(reference_c), time_constant_s_(time_constant_s) {
  if (model_ == Model::kTemperature) {
    parameters_.push_back({"expansion", "1/degC", 0.0, false, {}, {}, {},
                           "relative growth of the arm per degree above the reference"});
  } else {
    parameters_.push_back({"warmup_growth", "1", 0.0, false, {}, {}, {},
                           "relative growth of the arm once warm"});
  }
}

std::string ThermalDrift::Describe(const std::vector<double>& params) const {
  const double value = params.empty() ? 0.0 : params[0];
  return model_ == Model::kTemperature
             ? "thermal growth of the arm with temperature: " + Number(value) + " per degC"
             : "thermal growth of the arm while it warms up: " + Number(value * 1e6) +
                   " ppm (time constant " + Number(time_constant_s_) + " s)";
}

DepthBias::DepthBias(std::vector<std::string> cameras, bool scale, bool quadratic)
    : cameras_(std::move(cameras)), scale_(scale), quadratic_(quadratic),
      terms_per_camera_(int(scale) + int(quadratic)) {
  for (const auto& camera : cameras_) {
    if (scale_) {
      parameters_.push_back({camera + ".depth_scale", "1", 0.0, false, {}, {}, {},
                             "relative error of the measured distance"});
    }
    if (quadratic_) {
      parameters_.push_back({camera + ".depth_quadratic", "1/mm", 0.0, false, {}, {}, {},
                             "distance error growing with Z^2 (a disparity offset)"});
    }
  }
}

std::string DepthBias::Describe(const std::vector<double>& params) const {
  return WithParameters("camera depth bias", parameters_, params);
}

}  // namespace cellmetry::effects
