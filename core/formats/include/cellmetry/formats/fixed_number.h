// Numbers in tables and reports written with a fixed count of decimals ("12.35" for digits 2):
// the one helper for the summaries, markdown tables and reports that print figures for people
// (exact_number.h is for files programs read back).
#pragma once

#include <cstdio>
#include <string>

namespace cellmetry {

inline std::string FixedNumber(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

}  // namespace cellmetry
