// The cell identified again without each camera in turn (camera_left_out.h), internal to the
// cell layer: IdentifyWorkcell runs it last.
#pragma once

#include <vector>

#include "cellmetry/cell/camera_left_out.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/estimation/solver.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

// The static cameras that see a target the job's robots carry, sorted: what a camera-left-out
// refit and the camera jackknife (uncertainty_split.h) leave out in turn (none where fewer
// than two, or where cameras are not estimated).
std::vector<std::string> CamerasToLeaveOut(const WorkcellProblem& spec, const Recording& recording);

// For each camera of CamerasToLeaveOut, the cell identified on `recording` (the all-camera
// fit's, its outliers already left out) without it, by the same job with no cross-validation
// and no outlier test, against `all` (that fit's result). A camera whose cell cannot be
// identified without it gets its error, not an answer.
std::vector<CameraLeftOut> LeaveEachCameraOut(const WorkcellProblem& spec,
                                              const Recording& recording, const WorkcellResult& all,
                                              const SolverMaker& make_solver);

}  // namespace cellmetry
