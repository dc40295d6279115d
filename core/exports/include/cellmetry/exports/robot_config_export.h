// `cellmetry export --format robot`: the calibrated robot as a cellmetry robot config (the schema
// of configs/robots/*.yaml, the one its plugin reads), its fitted values as the nominal ones, for
// the next job's `model:`.
//
// The robot's model writes its own config (RobotModel::CalibratedConfig: the core knows no
// plugin's schema); the export puts the opening comment in front (where it came from, the fitted
// parameters with sigma, the effects a robot config cannot hold) and checks the text before
// handing it out: rebuilt through the registry, its parameters must equal the fitted values to
// the last bit (otherwise a bug in the plugin: std::logic_error). A plugin that cannot write its
// config is refused with an InputError that names --format tf.
#pragma once

#include <string>

#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

std::string RobotConfigExport(const CalibratedCell& cell, const CalibratedRobot& robot,
                              const Registry& registry);

}  // namespace cellmetry
