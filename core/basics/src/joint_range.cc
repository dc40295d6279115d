// Which joints a reading puts outside a calibration's ranges (joint_range.h).
#include "cellmetry/basics/joint_range.h"

#include <algorithm>

namespace cellmetry {

std::vector<int> JointsOutsideRanges(const JointRangesRad& ranges_rad,
                                     const std::vector<double>& q_rad) {
  std::vector<int> outside;
  const size_t joints = std::min(ranges_rad.size(), q_rad.size());
  for (size_t j = 0; j < joints; ++j) {
    const auto& [min_rad, max_rad] = ranges_rad[j];
    if (q_rad[j] < min_rad - kJointRangeToleranceRad ||
        q_rad[j] > max_rad + kJointRangeToleranceRad) {
      outside.push_back(static_cast<int>(j) + 1);
    }
  }
  return outside;
}

}  // namespace cellmetry
