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
#include <set>
#include <string>

#include "cellmetry/cell/workcell_data.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/estimation/noise_model.h"
#include "cellmetry/estimation/solver.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

WorkcellResult IdentifyWorkcell(const WorkcellProblem& spec, const Recording& recording,
                                const SolverMaker& make_solver);

// `spec.folds`-fold cross-validation by pose at `answer` (a part of IdentifyWorkcell, public for
// its benchmark): each fold refits on the other poses, warm-started from the answer with `held`
// held, and predicts the carried targets of the poses it left out. Fewer than two folds: none.
HeldOut CrossValidate(const WorkcellProblem& spec, const Recording& recording,
                      const WorkcellData& data, const NoiseModel& noise,
                      const WorkcellEstimate& answer, const HeldParameters& held,
                      const SolverMaker& make_solver);

// Two models' cross-validations on the same recording compared: before.total - after.total,
// and its standard error. Paired (RmsDifferenceStandardError, statistics.h) when both held out
// the same rows in the same folds, which the same poses, folds and seed give unless an outlier
// was left out of one fit; otherwise the two standard errors combined as independent, which
// overstates it. Like HeldOut::total_se_mm, it takes the poses as independent draws.
HeldOutGain CompareHeldOut(const HeldOut& before, const HeldOut& after);

// A result scored on a fresh recording of the same cell (a job's `validation_recording:`):
// prediction - measurement of the carried targets' positions, with the closed-form start and
// with the answer.
RecordingScore ScoreOnRecording(const WorkcellProblem& spec, const WorkcellResult& result,
                                const Recording& fresh);

}  // namespace cellmetry
