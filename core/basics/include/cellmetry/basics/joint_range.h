// Joint ranges: the interval of each joint's readings a calibration's poses span, and which joints
// a reading puts outside them. The held-out checks (cell/joint_ranges.h) and compensation judge a
// reading beyond a calibration with this one rule.
//
// Ranges are in the controller's readings, without wrapping: -200 deg is not 160 deg to a joint
// that turns past a full turn.
#pragma once

#include <utility>
#include <vector>

namespace cellmetry {

// Readings this close outside a range (rad) count as inside: a controller's reading of the same
// commanded angle differs in its last digits.
inline constexpr double kJointRangeToleranceRad = 1e-6;

// [min, max] per joint (rad), joint 1 first.
using JointRangesRad = std::vector<std::pair<double, double>>;

// The 1-based joints whose reading in `q_rad` lies outside its range by more than
// kJointRangeToleranceRad, in joint order. Joints beyond either list's end are not judged.
std::vector<int> JointsOutsideRanges(const JointRangesRad& ranges_rad,
                                     const std::vector<double>& q_rad);

}  // namespace cellmetry
