// A solver's `loss:` and `loss_scale:` options, read the same way by every solver that has them.
//
//   loss: none | huber | cauchy   (default none)
//   loss_scale: 1                 (mm: the residual size where the loss starts to bend; above 0)
//
// The solver hands both to Problem::SetRobustLoss, which divides the scale by each block's RMS
// sigma so that it acts on whitened residuals.
#pragma once

#include "cellmetry/estimation/problem.h"
#include "cellmetry/formats/config_node.h"

namespace cellmetry {

struct RobustLossOption {
  RobustLossKind kind = RobustLossKind::kNone;
  double scale_mm = 1.0;
};

// Reads `loss` and `loss_scale` from a solver's config; an unknown loss or a scale <= 0 is a
// ConfigError at its line.
RobustLossOption ReadRobustLossOption(const ConfigNode& config);

}  // namespace cellmetry
