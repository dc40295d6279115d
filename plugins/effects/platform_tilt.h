// PlatformTilt (`platform_tilt`): a delta arm's parallelograms out of true. When the two rods of
// arm i's parallelogram differ in length by dL_i, the platform can no longer stay parallel to
// the base: it tilts until every pair's rods fit again. To first order, with u_i the unit rod
// direction (platform toward elbow) and e_i the axis along which the pair's rods are spaced
// (RobotModel::ParallelLinks), the tilt w (rad, base frame) solves
//
//   (e_i x u_i) . w = dL_i / s_i = k_i          for the three arms
//
// (rod a's length changes by u_i . (w x s_i e_i / 2), rod b's by the opposite). The tilt turns
// the flange about the platform centre; a tool off the centre moves with it, and the tilt
// changes over the workspace as the rods turn. Parameters "arm<i>.skew" = k_i (rad: the rod
// length difference over the rod spacing). Acts on delta arms only (needs parallel links).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "cellmetry/basics/transform.h"
#include "parallel_link_effect.h"

namespace cellmetry::effects {

class PlatformTilt : public ParallelLinkEffect<PlatformTilt> {
 public:
  explicit PlatformTilt(std::vector<int> arms);

  std::string Describe(const std::vector<double>& params) const override;

  // values: p_base_flange[3], then R_base_flange[9] column-major (effect.h).
  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* values) const {
    Eigen::Matrix3d tilt_per_skew;
    if (!TiltPerSkew(context, &tilt_per_skew)) return;
    Vector3<T> w = Vector3<T>::Zero();
    for (size_t k = 0; k < arms_.size(); ++k) {
      w += tilt_per_skew.col(arms_[k]).cast<T>() * params[k];
    }
    const Matrix3<T> R_tilt = RotationFromRvec(w.data());
    Eigen::Map<Matrix3<T>> R_base_flange(values + 3);
    const Matrix3<T> turned = R_tilt * R_base_flange;
    R_base_flange = turned;
  }

 private:
  // Column i: the tilt (rad) per unit skew of arm i; false without three links.
  static bool TiltPerSkew(const EffectContext& context, Eigen::Matrix3d* tilt_per_skew);
};

}  // namespace cellmetry::effects
