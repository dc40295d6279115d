// CameraIntrinsics (`camera_intrinsics`): a camera's calibration slightly off, as it reaches a
// pose estimated from its image (PnP of a board). With normalized image coordinates x = X/Z,
// y = Y/Z and r^2 = x^2 + y^2:
//
//   focal length   f' = f (1 + e):      the board looks as large from (1 + e) times as far, and
//                                       lies on the same ray: Z' = Z (1 + e), X' = X, Y' = Y
//                                       (the measured depth alone scales: "<camera>.focal_scale");
//   principal point (cx + dx, cy + dy): every ray turns by (dx, dy) / f: x' = x - px, y' = y - py
//                                       ("<camera>.principal_x/y", rad); the measured rotation
//                                       turns with it, the board's apparent size (hence Z) does
//                                       not change. A static camera's pose takes the turn; what
//                                       a turned camera cannot give is the depth kept: a turn
//                                       moves Z by -px X, this does not, a depth error growing
//                                       across the image (experiment A: 2-4 % of the signature
//                                       outside the geometry, yet held-out 6.1 -> 3.3 mm);
//   radial distortion k1 off by k:      a point at radius r is imaged at r (1 + k r^2): the
//                                       board's direction scales by (1 + k r^2), its apparent
//                                       size by about (1 + 2 k r^2), so PnP puts it at
//                                       Z' = Z (1 - 2 k r^2) along x' = x (1 + k r^2)
//                                       ("<camera>.radial_k1", unitless, normalized radius).
//
// `cameras: [cam1]` (required), `terms: [focal, principal, radial]` (default all three).
#pragma once

#include <string>
#include <vector>

#include <ceres/rotation.h>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class CameraIntrinsics : public EffectFromTemplate<CameraIntrinsics> {
 public:
  CameraIntrinsics(std::vector<std::string> cameras, bool focal, bool principal, bool radial);

  EffectStage stage() const override { return EffectStage::kMeasurement; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* values) const {
    for (size_t c = 0; c < cameras_.size(); ++c) {
      if (cameras_[c] != context.camera) continue;
      const T* p = params + terms_per_camera_ * c;  // [focal] [px py] [k1]
      T x = values[0] / values[2], y = values[1] / values[2], z = values[2];
      if (radial_) {
        const T r2 = x * x + y * y;
        const T kr2 = p[focal_ + 2 * int(principal_)] * r2;
        x *= T(1.0) + kr2;
        y *= T(1.0) + kr2;
        z *= T(1.0) - T(2.0) * kr2;
      }
      if (principal_) {
        const T turn[3] = {p[focal_ + 1], -p[int(focal_)], T(0.0)};  // about y by px, x by -py
        x -= p[int(focal_)];
        y -= p[int(focal_) + 1];
        RotateMeasured(turn, values + 3);
      }
      if (focal_) z *= T(1.0) + p[0];
      values[0] = x * z;
      values[1] = y * z;
      values[2] = z;
    }
  }

 private:
  // R_cam_target (column-major, effect.h) turned by the small rotation `turn` (camera axes).
  template <typename T>
  static void RotateMeasured(const T* turn, T* R) {
    T Rt[9], out[9];
    ceres::AngleAxisToRotationMatrix(turn, Rt);
    for (int col = 0; col < 3; ++col) {
      for (int row = 0; row < 3; ++row) {
        T sum = T(0.0);
        for (int i = 0; i < 3; ++i) sum += Rt[3 * i + row] * R[3 * col + i];
        out[3 * col + row] = sum;
      }
    }
    for (int i = 0; i < 9; ++i) R[i] = out[i];
  }

  std::vector<std::string> cameras_;
  bool focal_, principal_, radial_;
  int terms_per_camera_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
