// DepthBias (`depth_bias`): a camera that measures distance slightly wrong. Stereo
// triangulation and PnP both put a target along its ray; a calibration error of the baseline or
// the focal length scales that distance, and a disparity offset adds a term that grows with Z^2
// (Z = f b / d: an offset dd in d moves Z by -Z^2 dd / (f b)):
//
//   p' = p (1 + a + b Z + t_x X/Z + t_y Y/Z)
//
// along the ray; per camera: "<camera>.depth_scale" (a, unitless), "<camera>.depth_quadratic"
// (b, 1/mm), Z = p's depth, and the tilt "<camera>.depth_tilt_x/y" (unitless): a distance error
// that changes across the image (X/Z, Y/Z are the ray's image coordinates), as a stereo rig's
// rectification turned slightly about an image axis, or a PnP with the principal point or the
// lens distortion off, makes it. A rigid move of the camera cannot take it up: it changes the
// distance alone, not the direction.
//
// `cameras: [cam1, cam2]` names the cameras (required); `terms: [scale, quadratic, tilt]`
// (default scale and quadratic) picks the terms.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class DepthBias : public EffectFromTemplate<DepthBias> {
 public:
  DepthBias(std::vector<std::string> cameras, bool scale, bool quadratic, bool tilt);

  EffectStage stage() const override { return EffectStage::kMeasurement; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* p_cam) const {
    for (size_t c = 0; c < cameras_.size(); ++c) {
      if (cameras_[c] != context.camera) continue;
      const T* p = params + terms_per_camera_ * c;
      T factor = T(1.0);
      int k = 0;
      if (scale_) factor += p[k++];
      if (quadratic_) factor += p[k++] * p_cam[2];
      if (tilt_) factor += (p[k] * p_cam[0] + p[k + 1] * p_cam[1]) / p_cam[2];
      for (int i = 0; i < 3; ++i) p_cam[i] *= factor;
    }
  }

 private:
  std::vector<std::string> cameras_;
  bool scale_, quadratic_, tilt_;
  int terms_per_camera_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
