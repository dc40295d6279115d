#include "cellmetry/frame_block.h"

namespace cellmetry {

std::vector<Parameter> FrameParameters(const FrameBlockSpec& spec) {
  std::vector<Parameter> params(6);
  for (int i = 0; i < 6; ++i) {
    params[i].name = kFrameParameterNames[i];
    params[i].unit = i < 3 ? "mm" : "rad";
    params[i].nominal = i < 3 ? spec.start.t[i] : 0.0;
    params[i].fixed = !spec.free[i];
    params[i].description = spec.description;
  }
  return params;
}

}  // namespace cellmetry
