// Plain words for effects' findings (describe.h): each parameter as "name = value unit", values
// to three significant digits.
#include "describe.h"

#include <cstdio>

namespace cellmetry::effects {

std::string Number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.3g", value);
  return buffer;
}

std::string WithParameters(const std::string& what, const std::vector<Parameter>& parameters,
                           const std::vector<double>& values) {
  std::string out = what;
  for (size_t k = 0; k < parameters.size() && k < values.size(); ++k) {
    out += (k ? ", " : ": ") + parameters[k].name + " = " + Number(values[k]) + " " +
           parameters[k].unit;
  }
  return out;
}

}  // namespace cellmetry::effects
