// Angles read wrongly: a recording whose joint readings and rotations are radians declared as
// degrees (or the reverse), an imported recording whose quaternion columns were mapped in the
// other order (scalar first for scalar last) or whose Euler angles were read in the other
// convention (intrinsic for extrinsic), or a robot config whose angles (twists, offsets)
// are radians declared `deg` (or the reverse), makes the nominal flange turn unlike the target
// the cameras see, and a fit on it "converges" metres away.
//
// CheckAngleUnits compares, for every robot, carried target and camera with measured rotations,
// how the target turns between two captures (R_i^T R_j) with how the robot's nominal model turns
// its flange between the same joint readings. The two are one rotation seen from two frames
// (hand-eye, AX = XB): their angles agree whatever the tool and the camera, and their axes differ
// by the tool's fixed rotation, so the angles between two turns' axes agree too. They differ by
// the noise and the model's error only. Where they differ by more than kAngleMismatchShare
// (TurnMismatch in the .cc: medians over the quarter of the pairs of captures that turn most),
// the same is tried with the recording's angles in the other unit, with the mapping's
// quaternion order swapped or its Euler angles turned about the other axes (`axes: intrinsic`
// for `extrinsic`, `rpy` as intrinsic XYZ; import.yaml, the mapping's copy in the recording),
// and with the robot config's angles in the other unit; a reading that agrees
// kAngleBetterFactor times better is refused as the likely mislabel, at the line to change. A
// share, not an angle: reading a recording's angles in another unit scales every turn. Skipped
// where fewer than three captures have rotations.
#pragma once

#include "cellmetry/cell/job.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

inline constexpr double kAngleMismatchShare = 0.02;  // real recordings agree within 0.3 %
inline constexpr double kAngleBetterFactor = 5.0;

void CheckAngleUnits(const WorkcellJob& job, const Recording& recording);

}  // namespace cellmetry
