// A robot's mounting tilting under the arm's overturning moment (base_tilt.h): its parameter, its
// description and the moment about the pivot.
#include "base_tilt.h"

#include "describe.h"

namespace cellmetry::effects {

BaseTilt::BaseTilt(std::vector<double> link_masses_kg, double pivot_mm)
    : link_masses_kg_(std::move(link_masses_kg)), pivot_mm_(pivot_mm) {
  parameters_.push_back({"base.compliance",
                         "rad/(N m)",
                         0.0,
                         false,
                         {},
                         {},
                         {},
                         "tilt of the mounting per N m of overturning moment",
                         {}});
  parameters_.back().plausible = 2e-5;              // a mounting softer than 5e4 N m/rad is unusual
  parameters_.back().plausible_nonnegative = true;  // it tilts with the load, not against it
}

std::string BaseTilt::Describe(const std::vector<double>& params) const {
  return WithParameters("the base tilting under the arm's moment", parameters_, params);
}

bool BaseTilt::OverturningMoment(const EffectContext& context, Eigen::Vector3d* moment_nm,
                                 Eigen::Vector3d* pivot_mm) const {
  if (!context.T_base_joint || context.T_base_joint->empty()) return false;
  const double g_norm = context.gravity_base.norm();
  if (!(g_norm > 0)) return false;
  const Eigen::Vector3d down = context.gravity_base / g_norm;
  *pivot_mm = pivot_mm_ * down;
  const Eigen::Vector3d pivot_m = 1e-3 * *pivot_mm;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const LumpedMass& mass :
       LumpedMasses(*context.T_base_joint, link_masses_kg_, context.payload_kg)) {
    moment += (mass.at_m - pivot_m).cross(mass.kg * context.gravity_base);
  }
  *moment_nm = moment - moment.dot(down) * down;  // about the vertical it turns joint 1 instead
  return true;
}

}  // namespace cellmetry::effects
