// The calibrated robot as a checked serial chain (robot_chain.h).
#include "cellmetry/exports/robot_chain.h"

#include <random>
#include <stdexcept>

#include "cellmetry/basics/error.h"

namespace cellmetry {

namespace {

// std::logic_error when `chain_pose` misses the model's forward kinematics at 64 joint vectors
// spread over +-2 pi: a bug in the plugin, never a file written wrong.
template <typename ChainPose>
void CheckAgainstForward(const CalibratedRobot& robot, const std::string& what,
                         const ChainPose& chain_pose) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> angle(-2.0 * M_PI, 2.0 * M_PI);
  std::vector<double> q(robot.model->num_joints());
  for (int trial = 0; trial < 64; ++trial) {
    for (double& v : q) v = angle(rng);
    Pose expected;
    if (!robot.model->Forward(q.data(), robot.values.data(), &expected)) continue;
    const Pose got = chain_pose(q.data());
    const double mm = (got.t - expected.t).norm();
    const double rad = RotationError(got.R, expected.R).norm();
    if (!(mm <= 1e-9) || !(rad <= 1e-12)) {
      throw std::logic_error("robot model " + robot.model_type + "'s " + what +
                             " misses its "
                             "forward kinematics by " +
                             std::to_string(mm) + " mm, " + std::to_string(rad) + " rad");
    }
  }
}

}  // namespace

SerialChain CalibratedChain(const CalibratedCell& cell, const CalibratedRobot& robot,
                            const std::string& format) {
  SerialChain chain;
  if (!robot.model->AsSerialChain(robot.values.data(), &chain)) {
    throw InputError({cell.json_path, 0, 0},
                     "robot '" + robot.name + "' (model " + robot.model_type +
                         ") is not a serial chain of revolute joints, which " + format +
                         " describes",
                     "Export it with --format robot (its calibrated config) or --format tf "
                     "(its frames)");
  }
  const int n = robot.model->num_joints();
  if (static_cast<int>(chain.T_parent_joint.size()) != n) {
    throw std::logic_error("robot model " + robot.model_type + " gave a chain of " +
                           std::to_string(chain.T_parent_joint.size()) + " joints for " +
                           std::to_string(n));
  }
  CheckAgainstForward(robot, "serial chain",
                      [&](const double* q) { return ChainFlangePose(chain, q); });
  return chain;
}

bool CalibratedNamedChain(const CalibratedRobot& robot, NamedChain* chain) {
  if (!robot.model->AsNamedChain(robot.values.data(), chain)) return false;
  int movable = 0;
  for (const NamedJoint& joint : chain->joints) movable += joint.movable ? 1 : 0;
  if (movable != robot.model->num_joints()) {
    throw std::logic_error("robot model " + robot.model_type + " named a chain of " +
                           std::to_string(movable) + " movable joints for " +
                           std::to_string(robot.model->num_joints()));
  }
  CheckAgainstForward(robot, "named chain",
                      [&](const double* q) { return NamedChainTipPose(*chain, q); });
  return true;
}

}  // namespace cellmetry
