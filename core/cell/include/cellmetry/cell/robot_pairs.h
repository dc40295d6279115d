// Every robot's base seen from every other robot's base (T_robotA_robotB), with its sigma
// propagated to first order from the joint covariance of both bases, their cross-covariance
// included (basics/relative_pose.h): in a cell where both robots are found through the same
// cameras, their bases' errors are correlated and the robot-to-robot transform is known better
// (or worse) than adding their sigmas says.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/basics/relative_pose.h"
#include "cellmetry/cell/workcell_result.h"

namespace cellmetry {

// The 12 x 12 covariance of (frame a's x y z rx ry rz, frame b's ...) from `u`: the total sigma
// of each entry times their correlation (as result.json states them and the exports read them);
// zero where an entry was held.
Eigen::Matrix<double, 12, 12> FramePairCovariance(const Uncertainty& u, const std::string& a,
                                                  const std::string& b);

// Every ordered pair of robots (b in a, and a in b: each with its sigma about its own parent's
// axes), in the result's order, both bases in the world.
std::vector<RobotPairEstimate> RobotToRobot(const WorkcellResult& result);

}  // namespace cellmetry
