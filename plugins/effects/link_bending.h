// LinkBending (`link_bending`): links that bend like beams under the gravity load they carry.
//
// A joint giving under gravity (joint_compliance.h) turns everything after it about the joint's
// axis. A link bending does not: its far end turns and also moves sideways by less than the turn
// about its root would carry it, so the two differ at the flange in how far it moves for how much
// it turns. Each selected link i is an Euler-Bernoulli beam from joint i's origin to joint i+1's
// (the flange for the last) at nominal geometry, of length L along e, flexibility c = 1/(E I)
// ("link<i>.flexibility", 1/(N m^2)). Loaded by the masses after it (link masses at their links'
// midpoints and the payload at the flange, LumpedMasses in effect.h) and its own mass spread
// along it, its bending moment at s in [0, L] from the root is
//
//   M(s) = A - s D + (L - s)^2 / 2 B,
//   A = sum_k (x_k - x_0) x m_k g,   D = e x sum_k m_k g,   B = e x (m_i g / L),
//
// of which the part across the beam bends it (its part along e would twist it; torsion is left
// out). Each slice turns what follows it by c M(s) ds, so at the flange
//
//   turn  Theta = c (A L - D L^2 / 2 + B L^3 / 6)
//   move  dp    = Theta x (p_flange - x_0) - c (A L^2 / 2 - D L^3 / 3 + B L^4 / 24) x e
//
// (a tip load P alone gives the textbook P L^2 / (2 E I) and P L^3 / (3 E I)). The load is taken
// at the nominal geometry, as the joint compliance's torque. A hollow cast-aluminium upper arm
// (E I about 4e5 N m^2) has c near 2.5e-6; one softer than 1e4 N m^2 would be unusual.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/model/effect.h"

namespace cellmetry::effects {

class LinkBending : public EffectFromTemplate<LinkBending> {
 public:
  // `links`: 0-based joint indices whose following link bends; `link_masses_kg` one per joint.
  LinkBending(std::vector<int> links, std::vector<double> link_masses_kg);

  EffectStage stage() const override { return EffectStage::kFlange; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  EffectNeeds needs() const override { return {.joint_frames = true}; }
  std::string Describe(const std::vector<double>& params) const override;

  // The flange's turn (rad) and move (mm), base frame, per unit flexibility of `link`, at the
  // context's nominal joint frames, under `masses` (LumpedMasses of those frames). False without
  // joint frames or for a link shorter than 1 mm.
  static bool BendingPerFlexibility(const EffectContext& context,
                                    const std::vector<LumpedMass>& masses, int link,
                                    Eigen::Vector3d* turn_rad, Eigen::Vector3d* move_mm);

  // values: p_base_flange[3], then R_base_flange[9] column-major (effect.h).
  template <typename T>
  void ApplyT(const EffectContext& context, const T* params, T* values) const {
    if (!context.T_base_joint || context.T_base_joint->empty()) return;
    const std::vector<LumpedMass> masses =
        LumpedMasses(*context.T_base_joint, link_masses_kg_, context.payload_kg);
    Vector3<T> turn = Vector3<T>::Zero();
    bool bent = false;
    for (size_t k = 0; k < links_.size(); ++k) {
      Eigen::Vector3d turn_rad, move_mm;
      if (!BendingPerFlexibility(context, masses, links_[k], &turn_rad, &move_mm)) continue;
      for (int i = 0; i < 3; ++i) values[i] += params[k] * move_mm[i];
      turn += turn_rad.cast<T>() * params[k];
      bent = true;
    }
    if (!bent) return;
    Eigen::Map<Matrix3<T>> R_base_flange(values + 3);
    const Matrix3<T> turned = RotationFromRvec(turn.data()) * R_base_flange;
    R_base_flange = turned;
  }

 private:
  std::vector<int> links_;
  std::vector<double> link_masses_kg_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::effects
