// RobotModel's defaults (robot_model.h): the failure messages, and no position inverse kinematics
// unless a model offers it.
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

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
