// FrameBlock (frame_block.h): a frame's six parameters (x y z in mm, rx ry rz in rad) and the
// `free:` list that frees them.
#include "cellmetry/model/frame_block.h"

#include <algorithm>
#include <set>

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

std::array<bool, 6> ReadFreeFlags(const ConfigNode& node, std::array<bool, 6> fallback) {
  if (!node.Has("free")) return fallback;
  const ConfigNode free = node["free"];
  std::array<bool, 6> flags{};
  const std::vector<std::string> names = free.AsStrings();
  std::set<std::string> seen;
  for (const auto& name : names) {
    if (!seen.insert(name).second) {
      throw free.Error("'" + name + "' appears twice in free", "Name each entry once");
    }
    if (name == "all") {
      flags.fill(true);
      continue;
    }
    if (name == "none") continue;
    const auto it = std::find(kFrameParameterNames.begin(), kFrameParameterNames.end(), name);
    if (it == kFrameParameterNames.end()) {
      const std::vector<std::string> known(kFrameParameterNames.begin(),
                                           kFrameParameterNames.end());
      const std::string nearest = NearestWord(name, known);
      throw free.Error("unknown frame parameter '" + name + "'",
                       (nearest.empty() ? "" : "Did you mean '" + nearest + "'? ") +
                           "Use x, y, z, rx, ry, rz, all or none");
    }
    flags[it - kFrameParameterNames.begin()] = true;
  }
  return flags;
}

}  // namespace cellmetry
