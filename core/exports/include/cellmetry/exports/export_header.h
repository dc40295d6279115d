// The opening comment every export carries: the marker that lets a later export replace it
// (export_file.h), where it came from, and what it leaves out. Each format wraps these lines in
// its own comment syntax (CommentLines).
#pragma once

#include <string>
#include <vector>

#include "cellmetry/exports/calibrated_cell.h"

namespace cellmetry {

// "cellmetry-export: <format> of <result.json>", the robot and its model when there is one, and
// that a later `command` to the same path replaces the file.
std::vector<std::string> ExportHeader(const CalibratedCell& cell, const std::string& format,
                                      const CalibratedRobot* robot,
                                      const std::string& command = "cellmetry export");

// What of `robot`'s result the export cannot hold: the model's own list (SerialChain's
// not_expressible, when `chain_gaps` is given), every effect fitted in its chain and on the
// cameras, with their values. Empty when nothing is left out.
std::vector<std::string> LeftOut(const CalibratedCell& cell, const CalibratedRobot& robot,
                                 const std::vector<std::string>& chain_gaps);

// Each line with `prefix` in front ("# ", "  "), joined with newlines.
std::string CommentLines(const std::vector<std::string>& lines, const std::string& prefix);

// "12.3 +- 0.045 mm" / "held": a fitted value with its sigma, for comments.
std::string ValueWithSigma(const FittedScalar& scalar);

// "<name> in <parent>: sigma xyz (0.07, 0.06, 0.2) mm, rot (1.2e-05, held, 3e-05) rad".
std::string FrameSigmaText(const CalibratedFrame& frame);

}  // namespace cellmetry
