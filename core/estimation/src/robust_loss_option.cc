// A solver's robust-loss options (robust_loss_option.h).
#include "cellmetry/estimation/robust_loss_option.h"

#include <string>

namespace cellmetry {

RobustLossOption ReadRobustLossOption(const ConfigNode& config) {
  RobustLossOption option;
  const std::string loss = config.GetString("loss", "none");
  if (loss == "huber") {
    option.kind = RobustLossKind::kHuber;
  } else if (loss == "cauchy") {
    option.kind = RobustLossKind::kCauchy;
  } else if (loss != "none") {
    throw config["loss"].Error("unknown loss '" + loss + "'", "Use none, huber or cauchy");
  }
  option.scale_mm = config.GetDoubleIn("loss_scale", option.scale_mm, 1e-12, 1e9,
                                       "Give the residual size (mm) where the loss bends, above 0");
  return option;
}

}  // namespace cellmetry
