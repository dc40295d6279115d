// A calibrated robot as a chain of revolute joints (serial_chain.h), for the exports that hold
// one (URDF, Universal Robots' kinematics YAML).
//
// The robot's model describes itself (RobotModel::AsSerialChain); the chain is then checked
// against the model's own forward kinematics at 64 joint vectors spread over +-2 pi, and a
// mismatch beyond 1e-9 mm or 1e-12 rad is a bug in the plugin (std::logic_error, exit code 1),
// never a file written wrong. A model that is no serial chain (a delta arm) is refused with an
// InputError that names the exports it does have. A model's own names and frames
// (named_chain.h) are checked alike.
#pragma once

#include <string>

#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/model/named_chain.h"
#include "cellmetry/model/serial_chain.h"

namespace cellmetry {

SerialChain CalibratedChain(const CalibratedCell& cell, const CalibratedRobot& robot,
                            const std::string& format);

// The robot under its own description's names (RobotModel::AsNamedChain), checked the same way;
// false when the model has none.
bool CalibratedNamedChain(const CalibratedRobot& robot, NamedChain* chain);

}  // namespace cellmetry
