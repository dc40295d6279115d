// The inputs part of a cell's uncertainty (internal to the cell layer): the job's uncertain
// inputs (workcell_problem.h, UncertainInputs) propagated into every estimate by the consider
// covariance (consider_covariance.h). A nominal kinematic table or a board's printed size is
// shared by every observation, so no resampling of the data sees its error; the user states
// how uncertain it is, and sigma carries it.
#pragma once

#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/estimation/estimation_quality.h"

namespace cellmetry {

// Sets `u`'s inputs part and adds it to the total (u->sigma must hold the statistical and
// systematic parts already). Nothing when the job names no uncertain inputs.
void AddInputUncertainty(const WorkcellProblem& spec, const Recording& recording,
                         const NoiseModel& noise, const WorkcellEstimate& answer, Uncertainty* u);

}  // namespace cellmetry
