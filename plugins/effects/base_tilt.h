// BaseTilt (`base_tilt`): a robot's mounting (its base flange on a pedestal, a table or a floor
// plate) tilting under the arm's overturning moment. Every joint turns the arm; the mounting
// turns all of it, about a pivot below the base frame:
//
//   theta = c M_h,    M_h = horizontal part of  sum_k (x_k - pivot) x m_k g
//
// c in rad/(N m), parameter "base.compliance"; x_k the link masses at their links' midpoints and
// the payload at the flange, LumpedMasses in effect.h (the first link's too: the mounting
// carries it); the pivot `pivot_mm` below the base frame's origin along gravity (where the base
// flange meets its mounting: the arm's shoulder height for a base frame on joint 2's axis). The
// flange turns by theta about the pivot:
//
//   p' = p + theta x (p - pivot),   R' = exp(theta) R.
//
// The part of the moment about the vertical turns joint 1, which joint 1's compliance is. The
// moment is taken at the nominal geometry. A robot bolted to a stiff floor tilts by
// 1e-7 to 1e-6 rad/(N m); a slender pedestal or a mobile base more; softer than 2e-5 is unusual.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class BaseTilt : public EffectFromTemplate<BaseTilt> {
 public:
  BaseTilt(std::vector<double> link_masses_kg, double pivot_mm);

  EffectStage stage() const override { return EffectStage::kFlange; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  EffectNeeds needs() const override { return {.joint_frames = true}; }
  std::string Describe(const std::vector<double>& params) const override;

  // The horizontal overturning moment about the pivot (N m, base frame) and the pivot (mm, base
  // frame) at the context's nominal joint frames; false without joint frames.
  bool OverturningMoment(const EffectContext& context, Eigen::Vector3d* moment_nm,
                         Eigen::Vector3d* pivot_mm) const;

  // values: p_base_flange[3], then R_base_flange[9] column-major (effect.h).
  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* values) const {
    Eigen::Vector3d moment_nm, pivot_mm;
    if (!OverturningMoment(context, &moment_nm, &pivot_mm)) return;
    const Vector3<T> turn = moment_nm.cast<T>() * params[0];
    Eigen::Map<Vector3<T>> p_base_flange(values);
    const Vector3<T> moved = p_base_flange + turn.cross(p_base_flange - pivot_mm.cast<T>());
    p_base_flange = moved;
    Eigen::Map<Matrix3<T>> R_base_flange(values + 3);
    const Matrix3<T> turned = RotationFromRvec(turn.data()) * R_base_flange;
    R_base_flange = turned;
  }

 private:
  std::vector<double> link_masses_kg_;
  double pivot_mm_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
