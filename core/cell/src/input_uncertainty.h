// The inputs part of a cell's uncertainty (internal to the cell layer): the job's uncertain
// inputs (workcell_problem.h, UncertainInputs) propagated into every estimate by the consider
// covariance (consider_covariance.h). A nominal kinematic table or a board's printed size is
// shared by every observation, so no resampling of the data sees its error; the user states
// how uncertain it is, and sigma carries it.
//
// Two steps. The link, the costly one: the cell assembled again with its inputs free
// (InputLinker), then one pass of normal equations at the fit's answer (InputLinker::LinkAt).
// The assembly needs only the fit's start, so it runs on another thread from the moment the start
// is known (input_link_schedule.h: beside the robust first fit's own assembly and solve, whose
// answer it is linked at), the pass from the moment the answer is. AddInputUncertainty then needs
// the fit's covariance.
//
// The link is assembled at the fit's start, so its frames turn about the same reference rotations
// (frame_block.h) and its columns are the fit's own parameters at the fit's own values: the
// covariance it is combined with is over those. (Assembled at the answer instead, a frame's
// rotation columns were about the answer's rotation: the fit's columns turned by the left
// Jacobian of the rotation solved, a relative difference of its size in radians.)
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/estimation/estimation_quality.h"

namespace cellmetry {

// How the answer leans on the uncertain inputs: J_t^T J_c over the estimated parameters and
// the inputs' parameters, and each input's standard uncertainty. Empty: no uncertain inputs.
struct InputLink {
  std::vector<std::string> estimated;  // the fit's free parameters, cross's row order
  std::vector<std::string> inputs;     // "<effect>.<parameter>", "<robot>.model.<parameter>"
  Eigen::VectorXd sigma;               // per input, in its unit
  Eigen::MatrixXd cross;               // estimated x inputs
};

// A fit's answer as the link reads it: every block's values and free parameters, and which
// block is which frame, model and effect (the fit's AssembledWorkcell, copied: the fit goes on
// changing its values after the answer, on another thread than the link's).
struct FitAnswer {
  std::vector<std::vector<double>> block_values;  // per block of the fit's problem
  std::vector<std::string> estimated;             // the fit's free parameters, in its order
  std::vector<int> base_block, model_block;
  std::vector<std::vector<int>> tool_block;
  std::map<std::string, int> camera_block;
  std::vector<int> effect_block;
  std::map<int, Eigen::Matrix3d> R_ref;
};

// `fit` as it is now.
FitAnswer AnswerOf(const AssembledWorkcell& fit);

// The estimate `fit` was assembled at, as far as an assembly reads it: its answer with each
// frame's rotation at the frame's reference rotation (what an InputLinker is assembled at for a
// fit whose start is not at hand).
WorkcellEstimate ReferenceEstimate(const WorkcellProblem& spec, const AssembledWorkcell& fit);

class InputLinker {
 public:
  // `spec` assembled with its uncertain inputs free at `start`, the start the fit to be linked
  // was assembled at; `data` is the fit's pairing of `recording`. Nothing is assembled when the
  // job has no uncertain inputs. `spec`, `recording`, `data` and `noise` are read here only.
  InputLinker(const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
              const NoiseModel& noise, const WorkcellEstimate& start);
  InputLinker(const InputLinker&) = delete;  // the assembly points into its own members
  InputLinker& operator=(const InputLinker&) = delete;

  // The link at `answer`, a fit of the same spec assembled at the same start (a fit whose
  // frames turn about other rotations is a programming error: std::logic_error). Throws
  // InputError where the model cannot be evaluated there with the inputs free.
  InputLink LinkAt(const FitAnswer& answer);

 private:
  std::map<std::string, double> input_sigma_;  // per input parameter
  WorkcellProblem augmented_;
  WorkcellData with_facts_;
  std::unique_ptr<AssembledWorkcell> assembled_;  // null: no uncertain inputs
};

// Sets `u`'s inputs part and adds it to the total (u->sigma must hold the statistical and
// systematic parts already, u->names the `estimated` of `link`: a link made at another fit's
// parameters is a programming error, std::logic_error). Nothing when `link` is empty.
void AddInputUncertainty(const InputLink& link, Uncertainty* u);

}  // namespace cellmetry
