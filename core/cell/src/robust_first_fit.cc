// The robust first fit (robust_first_fit.h): least squares, then a Cauchy loss at its scale.
#include "robust_first_fit.h"

#include <cmath>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/outliers.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_initial.h"
#include "residual_rows.h"

namespace cellmetry {
namespace {

// Sets the loss of each measurement block (rows are in block order) at `width` robust sigma of
// its group.
void SetLossFromScale(const std::vector<ResidualRow>& rows, double width, Problem* problem) {
  const std::vector<double> scale = RobustScales(rows);
  std::vector<double> whitened(scale.size());
  for (size_t i = 0; i < scale.size(); ++i) whitened[i] = width * std::sqrt(scale[i]);
  problem->SetWhitenedRobustLoss(RobustLossKind::kCauchy, std::move(whitened));
  problem->Build();
}

}  // namespace

std::vector<Outlier> FindOutliersByRobustFit(const WorkcellProblem& spec,
                                             const Recording& recording,
                                             const SolverMaker& make_solver,
                                             const RobustFirstFitOptions& options) {
  WorkcellProblem cartesian = spec;
  cartesian.residual = ResidualForm::kCartesian;
  const WorkcellData data = PrepareWorkcellData(cartesian, recording);
  const NoiseModel noise = BuildNoiseModel(recording, cartesian.noise);
  const WorkcellEstimate start = InitialEstimate(cartesian, recording, data);
  auto assembled = AssembleWorkcell(cartesian, recording, data, noise, start);
  Problem& problem = assembled->problem;
  if (problem.num_residuals() < problem.num_free()) return {};  // the plain fit says why
  try {
    // Plain least squares from the closed form first (a Cauchy loss from a start this far off
    // crawls: 200 iterations on exp_a), then the loss at the scale of that answer, warm.
    const IdentifiedSolve plain = SolveHoldingUnidentifiable(
        &problem, spec.identifiability_tolerance, {}, make_solver);
    std::set<std::string> held;
    for (const auto& u : plain.unidentifiable) held.insert(u.name);
    SetLossFromScale(ResidualRows(*assembled), options.cauchy_width, &problem);
    SolveHoldingUnidentifiable(&problem, spec.identifiability_tolerance, held, make_solver, true);
  } catch (const InputError& e) {
    Progress::Note(std::string("the robust first fit failed (") + e.what() +
                   "): outliers are tested on the plain fit only");
    return {};
  }
  return FindOutliers(ResidualRows(*assembled), recording, options.alpha);
}

}  // namespace cellmetry
