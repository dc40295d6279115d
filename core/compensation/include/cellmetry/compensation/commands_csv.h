// The commands `cellmetry compensate` writes (docs/results.md): one CSV row per target, in the
// order of TARGETS.csv, after '#' comment lines that say where they came from (the opening line
// carries the export marker, export_file.h, so that a later run may replace the file).
//
//   id, line, status ("ok" | "refused"), q1_rad ... q<n>_rad (the commands, every digit a
//   double has; empty when refused), error_mm, error_rad (remaining, predicted by the calibrated
//   chain), sigma_mm, sigma_rad (its sigma from the result's covariance; empty where the result
//   gives none), uncompensated_mm, uncompensated_rad (the robot config's nominal command's error
//   under the calibrated chain), approach_j1 ... approach_j<n>, beyond_calibration (the joints
//   the command puts outside the calibration's ranges, "2 5"; empty for none), reason (why
//   refused)
#pragma once

#include <string>
#include <vector>

#include "cellmetry/compensation/compensation.h"

namespace cellmetry {

// `comments`: lines for the opening comment (without '#').
std::string CompensatedCommandsCsv(const CompensationChain& chain,
                                   const std::vector<CompensatedCommand>& commands,
                                   const std::vector<std::string>& comments);

// The opening comment: marker and source, robot, tool and frame, the effects applied with their
// values, and what sigma covers.
std::vector<std::string> CompensationComments(const CalibratedCell& cell,
                                              const CompensationChain& chain);

}  // namespace cellmetry
