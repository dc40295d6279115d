// "3, 7, 12, ..." for failure messages that name marker or tag ids.
#pragma once

#include <string>
#include <vector>

namespace cellmetry::fiducial {

inline std::string IdList(const std::vector<int>& ids, size_t max_shown = 8) {
  std::string out;
  for (size_t i = 0; i < ids.size() && i < max_shown; ++i) {
    out += (i ? ", " : "") + std::to_string(ids[i]);
  }
  if (ids.size() > max_shown) out += ", ...";
  return out;
}

}  // namespace cellmetry::fiducial
