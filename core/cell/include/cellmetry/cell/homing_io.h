// Writing a visual homing result: homing.yaml (offsets in rad and motor increments by both
// methods, the positions used, the interval widths), written atomically; and the terminal summary.
#pragma once

#include <functional>
#include <string>

#include "cellmetry/cell/homing.h"

namespace cellmetry {

std::string HomingYaml(const HomingResult& result);
// `extra`: further files written into the staged folder before the commit (report.html).
void WriteHomingResult(const HomingResult& result, const std::string& folder,
                       const std::function<void(const std::string& staging)>& extra = {});
std::string HomingSummary(const HomingResult& result);

}  // namespace cellmetry
