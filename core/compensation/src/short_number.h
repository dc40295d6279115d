// A number in a message, four significant digits ("1.4", "0.0005", "1.235e+03").
#pragma once

#include <cstdio>
#include <string>

namespace cellmetry {

inline std::string ShortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.4g", value);
  return text;
}

}  // namespace cellmetry
