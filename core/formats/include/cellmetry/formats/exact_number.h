// Numbers in text files that read back as the same double.
//
// ExactNumber(x) is the shortest of %.15g, %.16g and %.17g that parses back to x exactly: 0.1
// stays "0.1", a fitted 119.85000000000002 keeps its last bit (zero's sign goes). Files other
// programs load (a calibrated robot config, a URDF, a kinematics YAML) use it, so that a round trip
// through them loses nothing.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace cellmetry {

inline std::string ExactNumber(double value) {
  if (value == 0.0) return "0";  // -0 reads back as 0 too, and "-0" puzzles a reader
  char text[40];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

}  // namespace cellmetry
