// A link bending as a beam under gravity (link_bending.h): its parameters, its description and the
// flange's turn and move per unit flexibility, integrated in closed form along the beam.
#include "link_bending.h"

#include "describe.h"

namespace cellmetry::effects {

LinkBending::LinkBending(std::vector<int> links, std::vector<double> link_masses_kg)
    : links_(std::move(links)), link_masses_kg_(std::move(link_masses_kg)) {
  for (int link : links_) {
    parameters_.push_back({"link" + std::to_string(link + 1) + ".flexibility",
                           "1/(N m^2)",
                           0.0,
                           false,
                           {},
                           {},
                           {},
                           "bending per N m of gravity moment per m of link, 1/(E I)",
                           {}});
    parameters_.back().plausible = 1e-4;  // a link softer than E I = 1e4 N m^2 is unusual
    parameters_.back().plausible_nonnegative = true;  // a link bends with gravity, not against
  }
}

std::string LinkBending::Describe(const std::vector<double>& params) const {
  std::string what = links_.size() == 1 ? "link " : "links ";
  for (size_t k = 0; k < links_.size(); ++k) {
    what += (k ? ", " : "") + std::to_string(links_[k] + 1);
  }
  return WithParameters(what + " bending under gravity", parameters_, params);
}

bool LinkBending::BendingPerFlexibility(const EffectContext& context,
                                        const std::vector<LumpedMass>& masses, int link,
                                        Eigen::Vector3d* turn_rad, Eigen::Vector3d* move_mm) {
  if (!context.T_base_joint || context.T_base_joint->empty()) return false;
  const std::vector<Pose>& frames = *context.T_base_joint;
  const int n = static_cast<int>(frames.size()) - 1;
  if (link < 0 || link >= n || masses.size() != frames.size()) return false;
  const Eigen::Vector3d root_m = 1e-3 * frames[link].t, tip_m = 1e-3 * frames[link + 1].t;
  const double length_m = (tip_m - root_m).norm();
  if (length_m < 1e-3) return false;
  const Eigen::Vector3d e = (tip_m - root_m) / length_m;
  const Eigen::Vector3d& g = context.gravity_base;
  // The loads after the link: each later link's mass at its midpoint, the payload at the flange.
  Eigen::Vector3d A = Eigen::Vector3d::Zero(), force = Eigen::Vector3d::Zero();
  for (size_t k = link + 1; k < masses.size(); ++k) {
    A += (masses[k].at_m - root_m).cross(masses[k].kg * g);
    force += masses[k].kg * g;
  }
  A -= A.dot(e) * e;  // bending only: the moment along the link would twist it
  const Eigen::Vector3d D = e.cross(force), B = e.cross(masses[link].kg * g / length_m);
  const double L = length_m;
  const Eigen::Vector3d turn = A * L - D * (L * L / 2) + B * (L * L * L / 6);
  const Eigen::Vector3d lag = A * (L * L / 2) - D * (L * L * L / 3) + B * (L * L * L * L / 24);
  const Eigen::Vector3d flange_m = 1e-3 * frames[n].t;
  *turn_rad = turn;
  *move_mm = 1e3 * (turn.cross(flange_m - root_m) - lag.cross(e));
  return true;
}

}  // namespace cellmetry::effects
