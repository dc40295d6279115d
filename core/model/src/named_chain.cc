// The product that defines a NamedChain (named_chain.h).
#include "cellmetry/model/named_chain.h"

#include <Eigen/Geometry>

namespace cellmetry {

Pose NamedChainTipPose(const NamedChain& chain, const double* q) {
  Pose T_base_link = Pose::Identity();
  int movable = 0;
  for (const NamedJoint& joint : chain.joints) {
    T_base_link = T_base_link * joint.T_parent_child;
    if (!joint.movable) continue;
    Pose turn;
    turn.R = Eigen::AngleAxisd(q[movable++], joint.axis).toRotationMatrix();
    T_base_link = T_base_link * turn;
  }
  return T_base_link;
}

}  // namespace cellmetry
