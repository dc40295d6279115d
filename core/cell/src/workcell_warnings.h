// The warnings of a cell's identification (internal to the cell layer): what the numbers of a
// result would not tell its user by themselves, said in the result (its `warnings`, in the
// order these are called) with what to do about it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/cell/workcell_data.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/formats/recording.h"
#include "far_start.h"

namespace cellmetry {

// What each robot model says of the values fitted to it (RobotModel::Warnings), for the robots
// whose model the job frees; `result` described already (DescribeEstimate).
void AddModelWarnings(const WorkcellProblem& spec, WorkcellResult* result);

// The fit's own warnings, once its uncertainty and parameters are in `result`: a solver that
// stopped before converging, a carried target's rotation freed but not fitted, parameters the
// data barely identifies (setting result->weakly_identified), an effect fitted beyond what its
// physics plausibly is, residuals well beyond the stated noise.
void AddWarnings(const WorkcellProblem& spec, WorkcellResult* result);

// A joint that never moves over the used samples while others do (StillJoints).
void AddStillJointWarnings(const WorkcellProblem& spec, const Recording& recording,
                           const WorkcellData& data, WorkcellResult* result);

// Each camera of result->cameras_left_out whose absence leaves the cell unidentifiable, or
// moves a base or a tool beyond the sigma of the difference.
void AddCameraLeftOutWarnings(WorkcellResult* result);

// Which of two fits was kept, one from the job's start that lies `far` from the data's closed
// form and one from that closed form (BetterOfTwoStarts): how well each predicts the carried
// targets (`given_mm`, or the given start's `given_failure`; `own_mm`), and whether they agree
// (`same`) or which was kept (`kept_given`). Added to `kept`.
void AddFarStartWarning(const std::vector<FarStart>& far, std::optional<double> given_mm,
                        const std::string& given_failure, double own_mm, bool same, bool kept_given,
                        WorkcellResult* kept);

}  // namespace cellmetry
