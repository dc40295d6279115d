// RobotModel's defaults (robot_model.h): the failure messages, and no position inverse kinematics
// unless a model offers it.
#include "cellmetry/model/robot_model.h"

#include <algorithm>

namespace cellmetry {

bool RobotModel::ForwardWithTwists(const double* q, const double* params, Pose* T_base_flange,
                                   Eigen::Matrix<double, 6, Eigen::Dynamic>* twists) const {
  const int n = static_cast<int>(parameters().size());
  if (!Forward(q, params, T_base_flange)) return false;
  twists->resize(6, n);
  std::vector<Jet> jets(params, params + n);
  for (int first = 0; first < n; first += kJetStride) {
    const int count = std::min(kJetStride, n - first);
    for (int k = 0; k < n; ++k) jets[k].v.setZero();
    for (int d = 0; d < count; ++d) jets[first + d].v[d] = 1.0;
    Transform<Jet> T;
    if (!Forward(q, jets.data(), &T)) return false;
    for (int d = 0; d < count; ++d) {
      Eigen::Matrix3d dR;
      for (int i = 0; i < 3; ++i) {
        (*twists)(i, first + d) = T.t[i].v[d];
        for (int j = 0; j < 3; ++j) dR(i, j) = T.R(i, j).v[d];
      }
      // dR R^T = [w]x: w from its skew part.
      const Eigen::Matrix3d W = dR * T_base_flange->R.transpose();
      twists->block<3, 1>(3, first + d) =
          0.5 * Eigen::Vector3d(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1));
    }
  }
  return true;
}

std::string RobotModel::ForwardFailure(const double*, const double*) const {
  return "the robot model has no pose for these joint values";
}

bool RobotModel::Inverse(const double*, const double*, double*) const { return false; }
bool RobotModel::Inverse(const Jet*, const Jet*, Jet*) const { return false; }

std::string RobotModel::InverseFailure(const double*, const double*) const {
  return has_inverse() ? "the point is out of the robot's reach"
                       : "this robot model has no position inverse kinematics";
}

}  // namespace cellmetry
