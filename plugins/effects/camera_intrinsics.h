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
//   lens distortion off by k1, k2 (radial) and p1, p2 (tangential) (Brown 1966, "Decentering
//   distortion of lenses", Photogrammetric Engineering 32; OpenCV's calib3d model without k3):
//                                       the board's centre is imaged at
//                                       x' = x (1 + k1 r^2 + k2 r^4) + 2 p1 x y + p2 (r^2 + 2 x^2)
//                                       y' = y (1 + k1 r^2 + k2 r^4) + p1 (r^2 + 2 y^2) + 2 p2 x y
//                                       and looks as large as the map's local stretch makes it
//                                       (sqrt det J, J its Jacobian), so PnP puts it at
//                                       Z' = Z / sqrt(det J) = Z (1 - tr(J - I) / 2) to first
//                                       order: Z (1 - 2 k1 r^2 - 3 k2 r^4 - 4 (p1 y + p2 x))
//                                       along (x', y') ("<camera>.radial_k1", "<camera>.radial_k2",
//                                       "<camera>.tangential_p1/p2", unitless, normalized image
//                                       coordinates); J is symmetric, so the board is not turned.
//
// `cameras: [cam1]` (required), `terms:` any of focal, principal, radial (k1), k2, tangential
// (default [focal, principal, radial]: the commonest three; a whole lens is [radial, k2,
// tangential]).
#pragma once

#include <string>
#include <vector>

#include <ceres/rotation.h>

#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

// Which of a camera's calibration terms an effect fits.
struct IntrinsicsTerms {
  bool focal = true, principal = true, radial = true;  // radial: k1
  bool k2 = false, tangential = false;
};

class CameraIntrinsics : public EffectFromTemplate<CameraIntrinsics> {
 public:
  CameraIntrinsics(std::vector<std::string> cameras, IntrinsicsTerms terms);

  EffectStage stage() const override { return EffectStage::kMeasurement; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  std::string Describe(const std::vector<double>& params) const override;

  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* values) const {
    for (size_t c = 0; c < cameras_.size(); ++c) {
      if (cameras_[c] != context.camera) continue;
      const T* p = params + terms_per_camera_ * c;  // [focal] [px py] [k1] [k2] [p1 p2]
      T x = values[0] / values[2], y = values[1] / values[2], z = values[2];
      if (lens_) Distort(p + lens_at_, &x, &y, &z);
      if (terms_.principal) {
        const T* principal = p + principal_at_;
        const T turn[3] = {principal[1], -principal[0], T(0.0)};  // about y by px, x by -py
        x -= principal[0];
        y -= principal[1];
        RotateMeasured(turn, values + 3);
      }
      if (terms_.focal) z *= T(1.0) + p[0];
      values[0] = x * z;
      values[1] = y * z;
      values[2] = z;
    }
  }

 private:
  // The board's centre (x, y) seen through the lens terms `lens` ([k1] [k2] [p1 p2], those
  // fitted) and its depth z as its apparent size gives it, to first order (the header's map).
  template <typename T>
  void Distort(const T* lens, T* x, T* y, T* z) const {
    const T r2 = *x * *x + *y * *y;
    T radial = T(0.0), stretch = T(0.0);  // stretch: tr(J - I) / 2
    if (terms_.radial) radial += *lens * r2, stretch += T(2.0) * *lens * r2, ++lens;
    if (terms_.k2) radial += *lens * r2 * r2, stretch += T(3.0) * *lens * r2 * r2, ++lens;
    T dx = *x * radial, dy = *y * radial;
    if (terms_.tangential) {
      const T p1 = lens[0], p2 = lens[1];
      dx += T(2.0) * p1 * *x * *y + p2 * (r2 + T(2.0) * *x * *x);
      dy += p1 * (r2 + T(2.0) * *y * *y) + T(2.0) * p2 * *x * *y;
      stretch += T(4.0) * (p1 * *y + p2 * *x);
    }
    *x += dx;
    *y += dy;
    *z *= T(1.0) - stretch;
  }

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
  IntrinsicsTerms terms_;
  bool lens_;                   // any of k1, k2, p1, p2
  int principal_at_, lens_at_;  // where a camera's principal point and lens terms start
  int terms_per_camera_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
