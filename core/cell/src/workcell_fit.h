// The fit steps of a cell's identification (internal to the cell layer): the robust first fit
// that starts the inputs' link, the fit with sigma, the rows a fit is judged by and their
// statistics. workcell_fit.cc also defines FitOnce and FirstFitSolver (fit_once.h) and the
// cross-validation (CrossValidate, workcell.h) that are built of them.
#pragma once

#include <set>
#include <vector>

#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_result.h"
#include "fit_once.h"
#include "input_link_schedule.h"
#include "robust_first_fit.h"

namespace cellmetry {

// A row that measures a robot: a target it carries, or the world target as a camera riding on
// it sees it (eye in hand).
bool MeasuresARobot(const Recording& recording, const ResidualRow& row);

// Prediction - measurement rows at `estimate`, in the measurement's units (mm / rad), whatever
// residual form the fit used: a joint-space fit's rows are whitened joint errors, so its
// measurements are compared again in the camera frame. `fitted`: the fit at `estimate`, whose
// rows are read where it is Cartesian (`at`: its linearization there); else, or where null,
// the rows are assembled anew at `estimate` on `poses` (empty: all).
std::vector<ResidualRow> MeasurementRows(const WorkcellProblem& spec, const Recording& recording,
                                         const WorkcellData& data, const NoiseModel& noise,
                                         const WorkcellEstimate& estimate,
                                         const std::set<int>& poses, AssembledWorkcell* fitted,
                                         const Linearization* at = nullptr);

// The robust first fit (robust_first_fit.h) with the uncertain inputs' link started at its
// least-squares start, in its LeastSquaresFit's schedule: that fit's answer is the plain fit's
// when nothing is left out (the usual case), so the link is assembled beside the fit's own
// assembly and solve, and linked at that answer alongside the Cauchy step and the test. Not
// where a sigma is unknown: FitWithSigma then solves again with sigma from this fit's
// residuals and links the inputs at that answer, and a link here would only take the other
// core from the fit (sim_b).
RobustFirstFit FindOutliersLinkingInputs(const WorkcellProblem& spec, const Recording& recording,
                                         const SolverMaker& make_solver);

// Solves; where sigma is unknown, estimates it from the first fit's residuals and solves again
// (variance component estimation), holding what the first fit found unidentifiable. `solved`:
// that first fit done already (LeastSquaresFit), taken instead of solving. Where it solves
// again, the uncertain inputs' link is started in `input_link` at that refit's start, assembled
// on the other core while the refit solves on the cores left, and answered with the refit's
// answer (`input_link` is left as it is otherwise). `spec`, `recording`, `data` and `noise`
// are what that link reads (input_link_schedule.h). Throws InputError where the recording
// gives fewer measured values than the job frees parameters.
Fit FitWithSigma(const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
                 const WorkcellEstimate& start, const SolverMaker& make_solver, NoiseModel* noise,
                 Fit* solved, InputLinkSchedule* input_link);

// Residual rows and their RMS per camera and target, in the measurement's units, at
// result->estimate with result->noise. `at`: the fit's linearization at its answer, whose
// residuals are taken (ResidualRows).
void AddResidualStatistics(const WorkcellProblem& spec, const Recording& recording,
                           const WorkcellData& data, const Fit& fit, const Linearization& at,
                           WorkcellResult* result);

}  // namespace cellmetry
