// The product that defines a SerialChain (serial_chain.h).
#include "cellmetry/model/serial_chain.h"

#include <cmath>

namespace cellmetry {

Pose TurnAboutZ(double angle_rad) {
  Pose turn;
  turn.R = Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return turn;
}

Pose ChainFlangePose(const SerialChain& chain, const double* q) {
  Pose T_base_joint = Pose::Identity();
  for (size_t i = 0; i < chain.T_parent_joint.size(); ++i) {
    T_base_joint = T_base_joint * chain.T_parent_joint[i] * TurnAboutZ(q[i]);
  }
  return T_base_joint * chain.T_last_joint_flange;
}

}  // namespace cellmetry
