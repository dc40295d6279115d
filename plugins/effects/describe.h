// Plain words for an effect's findings: "<what>: <name> = <value> <unit>, ...".
#pragma once

#include <string>
#include <vector>

#include "cellmetry/basics/parameter.h"

namespace cellmetry::effects {

// Three significant digits.
std::string Number(double value);

std::string WithParameters(const std::string& what, const std::vector<Parameter>& parameters,
                           const std::vector<double>& values);

}  // namespace cellmetry::effects
