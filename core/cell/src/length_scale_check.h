// Lengths a thousand times off: a recording that declares `length: m` but holds millimetres (or
// the reverse), or a robot config in the wrong unit, makes a cell a thousand times too large or
// too small, and a fit on it would "converge" to nonsense.
//
// CheckLengthScale compares, for every robot, tool target and camera, how far the observed
// target positions spread (RMS distance from their mean, in the camera: rotation does not
// change it) with how far the robot's nominal model moves its flange at the same recorded joint
// readings (robot config, base frame). The two describe one motion and agree to the tool's
// offset; a ratio beyond kLengthScaleLimit either way is refused with the likely cause. Which
// side is off, the target-to-camera distances tell: a camera sees its target between 2 cm and
// 20 m away. Outside that, the recording is blamed at recording.yaml's `units:` (about 1000
// times too large: millimetres declared as metres; too small: the reverse); inside it, the
// robot config at its `units:`. Skipped where the robot barely moves (flange spread below 1 mm)
// or fewer than three poses were seen.
#pragma once

#include "cellmetry/cell/job.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

inline constexpr double kLengthScaleLimit = 30.0;

void CheckLengthScale(const WorkcellJob& job, const Recording& recording);

}  // namespace cellmetry
