// TargetTilt (`target_tilt`, `world_frame`): the measured orientation of a target turned about
// its own x and y axes, position unchanged.
//
//   R' = R exp([t_x, t_y, 0])        per target: "<target>.tilt_x/y" (rad)
//
// `target_tilt`: the pose estimator's tilt of a planar board. A board seen at an angle, slightly
// unflat, or with its corners biased outward tilts in PnP by 10-30 mrad while its position stays
// within a few mm; every camera sees the same tilt where it comes from the board.
//
// `world_frame`: the world tag turned from the frame in which the robot's placement was measured
// (glued a little off level): R' = R exp([t_x, t_y, 0]), "world_frame.tilt_x/y"; with
// `axes: [x, y, z]` also turned in its plane ("tilt_z"). Everything the cell finds is in the tag's
// frame; with it, in the placement's. A gauge otherwise (turning the world turns every base and
// camera with it): it is determined only where a base's rotation is given, e.g. a robot placed
// square to the cell
// (`base: {free: [x, y, z]}`, its rotation held at the placement's).
//
// `targets: [tool]` for target_tilt (required); world_frame acts on the job's world target.
#pragma once

#include <string>
#include <vector>

#include <ceres/rotation.h>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class TargetTilt : public EffectFromTemplate<TargetTilt> {
 public:
  // `world`: the world_frame reading (its words and parameter names); `turn`: also about z
  // (world_frame only: where every base's rotation is given).
  TargetTilt(std::vector<std::string> targets, bool world, bool turn = false);

  EffectStage stage() const override { return EffectStage::kMeasurement; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* values) const {
    for (size_t t = 0; t < targets_.size(); ++t) {
      if (targets_[t] != context.target) continue;
      const int n = turn_ ? 3 : 2;
      const T tilt[3] = {params[n * t], params[n * t + 1], turn_ ? params[n * t + 2] : T(0.0)};
      T turn[9], out[9];
      ceres::AngleAxisToRotationMatrix(tilt, turn);  // column-major
      const T* R = values + 3;                       // R_cam_target, column-major
      for (int col = 0; col < 3; ++col) {
        for (int row = 0; row < 3; ++row) {
          T sum = T(0.0);
          for (int k = 0; k < 3; ++k) sum += R[3 * k + row] * turn[3 * col + k];
          out[3 * col + row] = sum;
        }
      }
      for (int i = 0; i < 9; ++i) values[3 + i] = out[i];
    }
  }

 private:
  std::vector<std::string> targets_;
  bool world_, turn_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
