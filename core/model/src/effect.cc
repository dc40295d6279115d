// The gravity torques effects share (effect.h): from lumped link masses at the joint frames or,
// without joint frames, from the load on the flange by virtual work.
#include "cellmetry/model/effect.h"

#include <algorithm>

namespace cellmetry {

std::vector<LumpedMass> LumpedMasses(const std::vector<Pose>& T_base_joint,
                                     const std::vector<double>& link_masses_kg, double payload_kg) {
  const int n = static_cast<int>(T_base_joint.size()) - 1;
  std::vector<LumpedMass> masses;
  for (int i = 0; i < n; ++i) {
    const double kg = i < static_cast<int>(link_masses_kg.size()) ? link_masses_kg[i] : 0.0;
    masses.push_back({kg, 0.5e-3 * (T_base_joint[i].t + T_base_joint[i + 1].t)});
  }
  if (n >= 0) masses.push_back({payload_kg, 1e-3 * T_base_joint[n].t});
  return masses;
}

std::vector<double> GravityTorques(const std::vector<Pose>& T_base_joint,
                                   const std::vector<double>& link_masses_kg, double payload_kg,
                                   const Eigen::Vector3d& gravity_base) {
  const int n = static_cast<int>(T_base_joint.size()) - 1;
  const std::vector<LumpedMass> masses = LumpedMasses(T_base_joint, link_masses_kg, payload_kg);
  std::vector<double> torque(std::max(n, 0), 0.0);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d origin = 1e-3 * T_base_joint[i].t, axis = T_base_joint[i].R.col(2);
    // Link i and everything after it (and the payload) turn with joint i.
    for (size_t k = i; k < masses.size(); ++k) {
      torque[i] += (masses[k].at_m - origin).cross(masses[k].kg * gravity_base).dot(axis);
    }
  }
  return torque;
}

std::vector<double> FlangeLoadTorques(const Eigen::Matrix3Xd& flange_jacobian_mm, double mass_kg,
                                      const Eigen::Vector3d& gravity_base) {
  // Virtual work: the load's force m g does work F . dp = (J^T F) . dq, J in m/rad.
  const Eigen::VectorXd torque = 1e-3 * flange_jacobian_mm.transpose() * (mass_kg * gravity_base);
  return std::vector<double>(torque.data(), torque.data() + torque.size());
}

std::vector<double> ContextGravityTorques(const EffectContext& context,
                                          const std::vector<double>& link_masses_kg) {
  if (context.T_base_joint && !context.T_base_joint->empty()) {
    return GravityTorques(*context.T_base_joint, link_masses_kg, context.payload_kg,
                          context.gravity_base);
  }
  if (context.flange_jacobian_mm && context.flange_jacobian_mm->cols() > 0) {
    double mass = context.payload_kg;
    for (double m : link_masses_kg) mass += m;
    return FlangeLoadTorques(*context.flange_jacobian_mm, mass, context.gravity_base);
  }
  return {};
}

}  // namespace cellmetry
