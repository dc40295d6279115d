// What a held-out setup's scored poses ask of compensation: each measured pose of a carried
// target, as TARGETS.csv (docs/formats.md, `cellmetry compensate`), in the world of the
// registered result (HeldOutSetupScore::registered), and the folder a result keeps them in.
//
// The instrument measured the target where the robot put it at the recorded joint readings; the
// registered camera frame carries that pose into the world. Compensated against the registered
// result, each row's command is what the calibrated model says reaches the measured pose, and
// the joints the robot reached it at are its seed (the configuration meant): the command minus
// the seed, carried through the arm, is the calibrated model's own error at that pose.
#pragma once

#include <string>

#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

// The scored poses' observations of `target` (a target some robot carries) in `held_out`,
// one row each: id ("pose P sample S"), x_mm y_mm z_mm, rx_rad ry_rad rz_rad where every row has
// a measured rotation, the seed q1_rad ... and payload_kg, temperature_c, t_s where every row's
// sample has them. `score.registered` must be set. Throws InputError when no scored pose saw
// the target.
std::string HeldOutTargetsCsv(const HeldOutSetupScore& score, const Recording& held_out,
                              const std::string& target);

// Writes `folder` (created; a result's staging folder's `held_out_setup/`): the registered
// result (result.yaml, result.json) and targets_<target>.csv for every carried target of
// `held_out`. Nothing when `score.registered` is unset.
void WriteHeldOutSetupFolder(const HeldOutSetupScore& score, const Recording& held_out,
                             const std::string& folder);

}  // namespace cellmetry
