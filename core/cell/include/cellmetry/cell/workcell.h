// IdentifyWorkcell: the workcell identification from recording to result.
//
//   pair observations -> noise model -> closed-form start -> hold unidentifiable parameters
//   -> solve -> (re-estimate unknown sigma from residuals, solve again) -> uncertainty,
//   residual statistics -> k-fold cross-validation by pose -> result
//
// The solver is any solver plugin; `make_solver` is called once per fit (folds included).
#pragma once

#include <functional>
#include <memory>

#include "cellmetry/formats/recording.h"
#include "cellmetry/estimation/solver.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/cell/workcell_result.h"

namespace cellmetry {


WorkcellResult IdentifyWorkcell(const WorkcellProblem& spec, const Recording& recording,
                                const SolverMaker& make_solver);

// A result scored on a fresh recording of the same cell (a job's `validation_recording:`):
// prediction - measurement of the carried targets' positions, with the closed-form start and
// with the answer.
RecordingScore ScoreOnRecording(const WorkcellProblem& spec, const WorkcellResult& result,
                                const Recording& fresh);

}  // namespace cellmetry
