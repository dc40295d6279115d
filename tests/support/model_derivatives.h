// A robot model's flange pose differentiated by one of its parameters two ways, for the tests
// that hold every derivative against central differences: by the model's Jet overload, and by
// central differences of its double overload.
//
// Contract:
//  - Parameter k is stepped by h = 1e-4 for a length in mm and 1e-7 otherwise (rad), either way
//    (p + h e_k, p - h e_k); the pose is T_base_flange as RobotModel::Forward gives it.
//  - The rotation's derivative is given both entry by entry (dR) and as the rotation vector of
//    R(p + h) R(p - h)^T over 2h (w, about the base's axes): the twist's rotation part.
#pragma once

#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry::testing {

// The flange pose's derivative by parameter k from central differences.
struct CentralDifference {
  double h = 0.0;      // the step
  Pose T_plus;         // the pose at p + h e_k
  Eigen::Vector3d dt;  // (t(p + h) - t(p - h)) / 2h, mm per unit of k
  Eigen::Matrix3d dR;  // (R(p + h) - R(p - h)) / 2h
  Eigen::Vector3d w;   // RotationError(R(p + h), R(p - h)) / 2h
};

inline CentralDifference CentralDifferenceByParameter(const RobotModel& model,
                                                      const std::vector<double>& q,
                                                      const std::vector<double>& params, int k) {
  CentralDifference d;
  d.h = model.parameters()[k].unit == "mm" ? 1e-4 : 1e-7;
  std::vector<double> plus = params, minus = params;
  plus[k] += d.h;
  minus[k] -= d.h;
  Pose T_minus;
  model.Forward(q.data(), plus.data(), &d.T_plus);
  model.Forward(q.data(), minus.data(), &T_minus);
  d.dt = (d.T_plus.t - T_minus.t) / (2 * d.h);
  d.dR = (d.T_plus.R - T_minus.R) / (2 * d.h);
  d.w = RotationError<double>(d.T_plus.R, T_minus.R) / (2 * d.h);
  return d;
}

// The flange pose on Jets with the derivative by parameter k seeded (its v[0]); false when the
// model's Forward fails there.
inline bool JetByParameter(const RobotModel& model, const std::vector<double>& q,
                           const std::vector<double>& params, int k, Transform<Jet>* T_jet) {
  std::vector<Jet> jets(params.size());
  for (size_t i = 0; i < params.size(); ++i) jets[i] = Jet(params[i]);
  jets[k].v[0] = 1.0;
  return model.Forward(q.data(), jets.data(), T_jet);
}

}  // namespace cellmetry::testing
