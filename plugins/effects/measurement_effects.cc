// Constructors and descriptions of the effects outside the joints (thermal_drift.h,
// depth_bias.h).
#include "depth_bias.h"
#include "describe.h"
#include "detection_bias.h"
#include "thermal_drift.h"

namespace cellmetry::effects {

ThermalDrift::ThermalDrift(Model model, double reference_c, double time_constant_s)
    : model_(model), reference_c_(reference_c), time_constant_s_(time_constant_s) {
  if (model_ == Model::kTemperature) {
    parameters_.push_back({"expansion",
                           "1/degC",
                           0.0,
                           false,
                           {},
                           {},
                           {},
                           "relative growth of the arm per degree above the reference",
                           {}});
    parameters_.back().plausible = 5e-5;  // twice aluminium's 2.3e-5 per degC
  } else {
    parameters_.push_back(
        {"warmup_growth", "1", 0.0, false, {}, {}, {}, "relative growth of the arm once warm", {}});
    parameters_.back().plausible = 1e-3;  // a millimetre per metre
  }
}

std::string ThermalDrift::Describe(const std::vector<double>& params) const {
  const double value = params.empty() ? 0.0 : params[0];
  return model_ == Model::kTemperature
             ? "thermal growth of the arm with temperature: " + Number(value) + " per degC"
             : "thermal growth of the arm while it warms up: " + Number(value * 1e6) +
                   " ppm (time constant " + Number(time_constant_s_) + " s)";
}

DepthBias::DepthBias(std::vector<std::string> cameras, bool scale, bool quadratic, bool tilt)
    : cameras_(std::move(cameras)), scale_(scale), quadratic_(quadratic), tilt_(tilt),
      terms_per_camera_(int(scale) + int(quadratic) + 2 * int(tilt)) {
  for (const auto& camera : cameras_) {
    if (scale_) {
      parameters_.push_back({camera + ".depth_scale",
                             "1",
                             0.0,
                             false,
                             {},
                             {},
                             {},
                             "relative error of the measured distance",
                             {}});
      parameters_.back().plausible = 0.05;  // 5 % of the distance
    }
    if (quadratic_) {
      parameters_.push_back({camera + ".depth_quadratic",
                             "1/mm",
                             0.0,
                             false,
                             {},
                             {},
                             {},
                             "distance error growing with Z^2 (a disparity offset)",
                             {}});
      parameters_.back().plausible = 1e-4;  // 10 % at a metre
    }
    if (tilt_) {
      for (const char* axis : {"x", "y"}) {
        parameters_.push_back({camera + ".depth_tilt_" + axis,
                               "1",
                               0.0,
                               false,
                               {},
                               {},
                               {},
                               std::string("distance error per unit image ") + axis +
                                   " (X/Z, Y/Z): a tilted depth field",
                               {}});
        parameters_.back().plausible = 0.05;  // 5 % across a unit of image
      }
    }
  }
}

std::string DepthBias::Describe(const std::vector<double>& params) const {
  return WithParameters(tilt_ && !scale_ && !quadratic_
                            ? "camera depth error tilting across the image"
                            : "camera depth bias",
                        parameters_, params);
}

DetectionBias::DetectionBias(std::vector<std::string> cameras, std::vector<std::string> targets,
                             const Eigen::Vector3d& prior_mm, double prior_rad,
                             bool in_target_frame)
    : cameras_(std::move(cameras)), targets_(std::move(targets)),
      in_target_frame_(in_target_frame) {
  for (const auto& camera : cameras_) {
    for (const auto& target : targets_) {
      const std::string axes = in_target_frame ? ", target axes" : ", camera axes";
      for (int axis = 0; axis < 3; ++axis) {
        parameters_.push_back({camera + "." + target + ".bias_" + "xyz"[axis],
                               "mm",
                               0.0,
                               false,
                               {},
                               {},
                               prior_mm[axis],
                               "systematic detection error" + axes,
                               {}});
      }
      for (int axis = 0; axis < 3; ++axis) {
        parameters_.push_back({camera + "." + target + ".bias_r" + "xyz"[axis],
                               "rad",
                               0.0,
                               false,
                               {},
                               {},
                               prior_rad,
                               "systematic detection rotation" + axes,
                               {}});
      }
    }
  }
}

std::string DetectionBias::Describe(const std::vector<double>& params) const {
  return WithParameters("systematic detection error", parameters_, params);
}

}  // namespace cellmetry::effects
