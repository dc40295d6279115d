// Writing a visual homing result: homing.yaml (offsets in rad and motor increments by both
// methods, the positions used, the interval widths), written atomically; and the terminal summary.
#pragma once

#include <string>

#include "cellmetry/cell/homing.h"

namespace cellmetry {

std::string HomingYaml(const HomingResult& result);
void WriteHomingResult(const HomingResult& result, const std::string& folder);
std::string HomingSummary(const HomingResult& result);

}  // namespace cellmetry
