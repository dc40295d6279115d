// DetectionBias (`detection_bias`): a marker detector's systematic error. A camera that sees a
// target from much the same side every time (a static board; a tool that always faces it) makes
// the same error every time: a few hundredths of a pixel of corner bias become a constant offset
// of the measured position in that camera's frame, mostly along depth, which no averaging
// removes:
//
//   p' = p + b         b in mm, camera axes; parameters "<camera>.<target>.bias_x/y/z"
//
// `cameras: [...]`, `targets: [...]` (every pair gets a bias), `prior_mm` (x, y, depth; default
// [0.1, 0.1, 0.3], or one number for all three): the bias's expected size, a Gaussian prior on
// each component. Put it in a job to make the
// uncertainty honest where views repeat: the bias is then a nuisance the estimate carries.
#pragma once

#include <string>
#include <vector>

#include <ceres/rotation.h>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class DetectionBias : public EffectFromTemplate<DetectionBias> {
 public:
  DetectionBias(std::vector<std::string> cameras, std::vector<std::string> targets,
                const Eigen::Vector3d& prior_mm, double prior_rad, bool in_target_frame);

  EffectStage stage() const override { return EffectStage::kMeasurement; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* p_cam) const {
    for (size_t c = 0; c < cameras_.size(); ++c) {
      if (cameras_[c] != context.camera) continue;
      for (size_t t = 0; t < targets_.size(); ++t) {
        if (targets_[t] != context.target) continue;
        const T* b = params + 6 * (c * targets_.size() + t);  // x, y, z, rx, ry, rz
        T* R = p_cam + 3;  // column-major R_cam_target (effect.h)
        for (int i = 0; i < 3; ++i) {
          p_cam[i] += in_target_frame_ ? R[i] * b[0] + R[3 + i] * b[1] + R[6 + i] * b[2] : b[i];
        }
        T turn[9], turned[9];
        ceres::AngleAxisToRotationMatrix(b + 3, turn);  // column-major
        for (int col = 0; col < 3; ++col) {
          for (int row = 0; row < 3; ++row) {
            T sum = T(0.0);
            for (int k = 0; k < 3; ++k) {
              sum += in_target_frame_ ? R[3 * k + row] * turn[3 * col + k]
                                      : turn[3 * k + row] * R[3 * col + k];
            }
            turned[3 * col + row] = sum;
          }
        }
        for (int i = 0; i < 9; ++i) R[i] = turned[i];
      }
    }
  }

 private:
  std::vector<std::string> cameras_, targets_;
  bool in_target_frame_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
