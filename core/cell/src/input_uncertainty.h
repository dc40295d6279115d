// The inputs part of a cell's uncertainty (internal to the cell layer): the job's uncertain
// inputs (workcell_problem.h, UncertainInputs) propagated into every estimate by the consider
// covariance (consider_covariance.h). A nominal kinematic table or a board's printed size is
// shared by every observation, so no resampling of the data sees its error; the user states
// how uncertain it is, and sigma carries it.
//
// Two steps: LinkInputs, the costly one (the cell assembled again with its inputs free, one
// pass of normal equations at the answer), needs only the answer, so it runs on another thread
// from the moment the answer is known (workcell.cc: from the robust first fit's least-squares
// answer where that is the plain fit's); AddInputUncertainty then needs the fit's covariance.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/estimation/estimation_quality.h"

namespace cellmetry {

// How the answer leans on the uncertain inputs: J_t^T J_c over the estimated parameters and
// the inputs' parameters, and each input's standard uncertainty. Empty: no uncertain inputs.
struct InputLink {
  std::vector<std::string> estimated;  // the fit's free parameters, cross's row order
  std::vector<std::string> inputs;  // "<effect>.<parameter>", "<robot>.model.<parameter>"
  Eigen::VectorXd sigma;            // per input, in its unit
  Eigen::MatrixXd cross;            // estimated x inputs
};

// At `answer`, for the parameters `estimated` (the fit's free parameters, in its order);
// `data` is the fit's pairing of `recording`. Throws InputError where the model cannot be
// evaluated there with the inputs free.
InputLink LinkInputs(const WorkcellProblem& spec, const Recording& recording,
                     const WorkcellData& data, const NoiseModel& noise,
                     const WorkcellEstimate& answer, const std::vector<std::string>& estimated);

// Sets `u`'s inputs part and adds it to the total (u->sigma must hold the statistical and
// systematic parts already, u->names the `estimated` of `link`: a link made at another fit's
// parameters is a programming error, std::logic_error). Nothing when `link` is empty.
void AddInputUncertainty(const InputLink& link, Uncertainty* u);

}  // namespace cellmetry
