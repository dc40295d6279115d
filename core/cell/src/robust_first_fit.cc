// The robust first fit (robust_first_fit.h): least squares, then a Cauchy loss at its scale.
#include "robust_first_fit.h"

#include <algorithm>
#include <cmath>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/outliers.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/estimation/reweighted_solve.h"
#include "residual_rows.h"

namespace cellmetry {
namespace {

// Sets the loss of each measurement block at `width` robust sigma of its group, at the whitened
// residuals `whitened` of the problem's current values.
void SetLossFromScale(const Eigen::VectorXd& whitened, double width, AssembledWorkcell* assembled) {
  Problem* problem = &assembled->problem;
  const std::vector<double> scale = RobustScales(*assembled, whitened);
  std::vector<double> loss_scale(scale.size());
  for (size_t i = 0; i < scale.size(); ++i) loss_scale[i] = width * std::sqrt(scale[i]);
  problem->SetWhitenedRobustLoss(RobustLossKind::kCauchy, std::move(loss_scale));
  problem->Build();
}

// Every block's values and held entries: what the Cauchy solve changes in a problem that the
// least-squares fit must get back as it left it.
struct BlockStates {
  std::vector<std::vector<double>> values;
  std::vector<std::vector<bool>> fixed;
};

BlockStates Snapshot(Problem& problem) {
  BlockStates states;
  for (int b = 0; b < problem.num_blocks(); ++b) {
    const auto& params = problem.block_parameters(b);
    states.values.emplace_back(problem.values(b), problem.values(b) + params.size());
    std::vector<bool> fixed;
    for (const Parameter& p : params) fixed.push_back(p.fixed);
    states.fixed.push_back(std::move(fixed));
  }
  return states;
}

// The least-squares problem again: values and held entries as snapshot, no loss.
void Restore(const BlockStates& states, Problem* problem) {
  for (int b = 0; b < problem->num_blocks(); ++b) {
    std::copy(states.values[b].begin(), states.values[b].end(), problem->values(b));
    for (size_t i = 0; i < states.fixed[b].size(); ++i) {
      problem->SetFixed(b, static_cast<int>(i), states.fixed[b][i]);
    }
  }
  problem->SetWhitenedRobustLoss(RobustLossKind::kNone, {});
  problem->Build();
}

}  // namespace

RobustFirstFit FindOutliersByRobustFit(const WorkcellProblem& spec, const Recording& recording,
                                       const SolverMaker& make_solver,
                                       const RobustFirstFitOptions& options) {
  auto ls = std::make_unique<LeastSquaresFit>();  // at one address: the residuals point into it
  ls->spec = spec;
  ls->spec.residual = ResidualForm::kCartesian;
  ls->inputs = PrepareFitInputs(ls->spec, recording);
  const bool kept = spec.residual == ResidualForm::kCartesian;  // the plain fit's first solve
  const bool work_beside =
      kept && options.at_least_squares_start && options.at_least_squares_start(ls.get());
  Fit& fit = ls->fit;
  fit.assembled =
      AssembleWorkcell(ls->spec, recording, ls->inputs.data, ls->inputs.noise, ls->inputs.start);
  Problem& problem = fit.assembled->problem;
  fit.free_as_asked = problem.num_free();
  if (problem.num_residuals() < problem.num_free()) return {};  // the plain fit says why
  RobustFirstFit out;
  try {
    // Plain least squares from the closed form first (a Cauchy loss from a start this far off
    // crawls: 200 iterations on exp_a), then the loss at the scale of that answer, warm.
    const SolverMaker first_solver = FirstFitSolver(ls->inputs.noise, make_solver);
    IdentifiedSolve plain =
        SolveHoldingUnidentifiable(&problem, spec.identifiability_tolerance, {},
                                   work_beside ? LeavingOneCore(first_solver) : first_solver);
    const HeldParameters held = HeldOf(plain.unidentifiable);
    fit.summary = plain.summary;
    fit.unidentifiable = std::move(plain.unidentifiable);
    fit.at_answer = std::move(plain.at_answer);
    if (kept && options.at_least_squares_answer) options.at_least_squares_answer(ls.get());
    const BlockStates least_squares = Snapshot(problem);
    SetLossFromScale(WhitenedResiduals(problem, &fit.at_answer), options.cauchy_width,
                     fit.assembled.get());
    if (!SolveByReweighting(&problem).converged) {
      // Far from the robust answer (least squares dragged off by gross errors, or not
      // converged): the job's solver takes over from where the reweighting stopped.
      SolveHoldingUnidentifiable(&problem, spec.identifiability_tolerance, held, make_solver,
                                 /*warm_start=*/true);
    }
    out.outliers =
        FindOutliers(*fit.assembled, WhitenedResiduals(problem), recording, options.alpha);
    Restore(least_squares, &problem);
  } catch (const InputError& e) {
    Progress::Note(std::string("the robust first fit failed (") + e.what() +
                   "): outliers are tested on the plain fit only");
    return {};
  }
  if (kept) out.least_squares = std::move(ls);
  return out;
}

}  // namespace cellmetry
