// The robust first fit (robust_first_fit.h): Cauchy loss, scale re-measured at each answer.
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
// its group; returns the groups' scales for the next round's comparison.
std::vector<double> SetLossFromScale(const std::vector<ResidualRow>& rows, double width,
                                     Problem* problem) {
  std::vector<double> scale = RobustScales(rows);
  std::vector<double> whitened(scale.size());
  for (size_t i = 0; i < scale.size(); ++i) whitened[i] = width * std::sqrt(scale[i]);
  problem->SetWhitenedRobustLoss(RobustLossKind::kCauchy, std::move(whitened));
  problem->Build();
  return scale;
}

bool Settled(const std::vector<double>& before, const std::vector<double>& after) {
  for (size_t i = 0; i < before.size(); ++i) {
    if (std::abs(after[i] - before[i]) > 0.05 * before[i]) return false;
  }
  return true;
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
  std::vector<ResidualRow> rows = ResidualRows(*assembled);
  std::set<std::string> held;
  try {
    for (int round = 0; round < options.max_rounds; ++round) {
      const std::vector<double> scale = SetLossFromScale(rows, options.cauchy_width, &problem);
      const IdentifiedSolve solved = SolveHoldingUnidentifiable(
          &problem, spec.identifiability_tolerance, held, make_solver, round > 0);
      for (const auto& u : solved.unidentifiable) held.insert(u.name);
      rows = ResidualRows(*assembled);
      if (round > 0 && Settled(scale, RobustScales(rows))) break;
    }
  } catch (const InputError& e) {
    Progress::Note(std::string("the robust first fit failed (") + e.what() +
                   "): outliers are tested on the plain fit only");
    return {};
  }
  return FindOutliers(rows, recording, options.alpha);
}

}  // namespace cellmetry
