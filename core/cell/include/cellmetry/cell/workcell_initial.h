// Closed-form starting values for a workcell identification: a user never types a guess.
//
//  1. Static cameras: T_world_cam from the mean of the camera's world-target observations
//     (chordal mean rotation, mean translation).
//  2. Each robot: the measured target positions are carried into the world frame; then, with the
//     tool offset at its nominal value, Kabsch gives T_world_base; with that rotation, a linear
//     least-squares step gives the base translation and every free tool translation jointly;
//     the two steps alternate until the change is below 1e-9 mm (at most 50 rounds).
//  3. Tool rotations (only when target rotations are fitted): chordal mean of
//     (R_world_base R_base_flange)^T R_world_target over the captures.
//  4. Static cameras that never see the world target: Kabsch between the targets' predicted
//     world positions and their measured camera-frame positions.
#pragma once

#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

// The problem's warm start where it places everything the data uses (WorkcellProblem::
// warm_start); otherwise the closed form, which raises InputError when a robot has fewer than
// three usable, non-collinear measurements.
WorkcellEstimate InitialEstimate(const WorkcellProblem& spec, const Recording& recording,
                                 const WorkcellData& data);

}  // namespace cellmetry
