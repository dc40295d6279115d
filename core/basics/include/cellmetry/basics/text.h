// Small pieces of text every layer's messages and reports are made of: a list joined with a
// separator, a length in millimetres, an angle in degrees.
//
// Contract:
//  - Join puts `separator` between every two neighbours (none before the first or after the
//    last); an empty list is "".
//  - Mm writes a length in mm with `significant_digits` significant digits (printf's %g,
//    so no trailing zeros and an exponent for very large or small values) and " mm".
//  - Degrees writes an angle given in rad as degrees with `decimals` decimals and no unit.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace cellmetry {

// {"x", "y", "z"} -> "x, y, z".
inline std::string Join(const std::vector<std::string>& items,
                        const std::string& separator = ", ") {
  std::string text;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i > 0) text += separator;
    text += items[i];
  }
  return text;
}

// 12.3456 -> "12.3 mm" (3 digits), "12.35 mm" (4 digits).
inline std::string Mm(double length_mm, int significant_digits = 3) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*g mm", significant_digits, length_mm);
  return text;
}

// 0.5 rad -> "28.6" (1 decimal).
inline std::string Degrees(double angle_rad, int decimals = 1) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", decimals, angle_rad * 180.0 / M_PI);
  return text;
}

}  // namespace cellmetry
