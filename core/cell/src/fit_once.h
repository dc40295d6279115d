// One fit of a cell (internal to the cell layer): assemble on some poses, hold what the data
// cannot determine, solve. workcell_fit.cc defines it; the fit with sigma and each fold of the
// cross-validation are made of it.
#pragma once

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/estimation/estimation_quality.h"
#include "input_link_schedule.h"

namespace cellmetry {

// What a fit of a recording starts from: its observations paired with the job's robots and
// cameras, the spread of its repeated captures, the noise model of both, the closed-form start.
struct FitInputs {
  WorkcellData data;
  NoiseModel repeatability;  // EstimateRepeatability of the recording
  NoiseModel noise;
  WorkcellEstimate start;
};

// `recording`'s FitInputs for `spec`. The repeat spread needs the recording alone: it is found
// on another thread while this one pairs the data and finds the start.
FitInputs PrepareFitInputs(const WorkcellProblem& spec, const Recording& recording);

struct Fit {
  std::unique_ptr<AssembledWorkcell> assembled;
  SolverSummary summary;
  std::vector<UnidentifiableParameter> unidentifiable;
  int free_as_asked = 0;    // free parameters before anything was held as unidentifiable
  Linearization at_answer;  // IdentifiedSolve's: valid when the solve's last check held nothing
};

// The least-squares fit of a whole recording that the robust first fit solves on its way to
// the Cauchy one (robust_first_fit.h), left at its answer. For a Cartesian job it is the plain
// fit's first solve exactly (the same problem from the same start by the same solver), so when
// the robust fit leaves nothing out IdentifyOnce takes it instead of solving again: on exp_a
// that solve and its assembly were a third of the identification. The residuals keep pointers
// into `spec` and `inputs.data` (AssembleWorkcell): they live together, at one address.
struct LeastSquaresFit {
  WorkcellProblem spec;
  FitInputs inputs;
  Fit fit;
  // How the answer leans on the job's uncertain inputs (input_uncertainty.h), worked out on
  // another core: assembled from the moment the start is known, beside this fit's own assembly
  // and solve, and linked at the fit's answer while the robust fit's Cauchy step and outlier
  // test run (FindOutliersLinkingInputs starts and answers it): IdentifyOnce takes it when it
  // takes this fit unchanged. After what it reads, so that it goes first: a fit given up before
  // its answer ends the link, which is waited for before `spec` and `inputs` go
  // (input_link_schedule.h).
  InputLinkSchedule input_link;
};

// The solver of a cell's first fit: where a sigma is unknown, that fit's answer is read only for
// its residuals (FitWithSigma refits with the sigma they give, by the job's solver), so the
// core's Levenberg-Marquardt on the normal equations solves it, to the same minimum within
// 1.4e-5 of a sigma (reweighted_solve.h, decrement 1e-10); else the job's solver, whose answer
// that fit is.
SolverMaker FirstFitSolver(const NoiseModel& noise, const SolverMaker& job_solver);

// Assembles on `poses` (empty: all), holds `held` and whatever the data cannot determine, and
// solves from `start` (`warm_start`: a neighbouring fit's answer; SolveHoldingUnidentifiable).
Fit FitOnce(const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
            const NoiseModel& noise, const WorkcellEstimate& start, const std::set<int>& poses,
            HeldParameters held, const SolverMaker& make_solver, bool warm_start = false);

}  // namespace cellmetry
