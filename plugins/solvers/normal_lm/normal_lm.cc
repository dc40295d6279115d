// `normal_lm`: Levenberg-Marquardt on the normal equations the core sums block by block.
//
// The core's SolveByReweighting (cellmetry/estimation/reweighted_solve.h) offered to jobs: each
// iteration sums J^T J and J^T r over the residual blocks (Problem::EvaluateNormalEquations)
// and solves the damped n x n system. For a cell's few dozen to few hundred free parameters
// against tens of thousands of blocks that is a fraction of ceres_lm's iteration, whose cost is
// Ceres's work per block (docs/benchmarks.md); the answer is the same least-squares minimum.
// For problems that live on their bounds or have thousands of free parameters, use ceres_lm.
//
// Options (defaults): max_iterations 200; decrement_tolerance 1e-10 (stop when the Gauss-Newton
// step would lower the whitened cost by less: every parameter within 1.4e-5 of its sigma of the
// minimum); loss none|huber|cauchy; loss_scale 1 (mm, as ceres_lm's).
#include "cellmetry/estimation/problem.h"
#include "cellmetry/estimation/reweighted_solve.h"
#include "cellmetry/estimation/robust_loss_option.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry::normal_lm {
namespace {

struct Options {
  ReweightedSolveOptions solve;
  RobustLossKind loss = RobustLossKind::kNone;
  double loss_scale = 1.0;
};

class NormalLm : public Solver {
 public:
  explicit NormalLm(Options options) : options_(options) {}

  SolverSummary Solve(Problem& problem) override {
    if (options_.loss != RobustLossKind::kNone) {
      problem.SetRobustLoss(options_.loss, options_.loss_scale);
      problem.Build();
    }
    SolverSummary summary = SolveByReweighting(&problem, options_.solve);
    summary.solver = "normal_lm";
    return summary;
  }

 private:
  Options options_;
};

std::unique_ptr<Solver> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "max_iterations", "decrement_tolerance", "loss", "loss_scale"});
  Options o;
  o.solve.decrement_tolerance = 1e-10;
  o.solve.max_iterations = config.GetIntIn("max_iterations", o.solve.max_iterations, 1, 1000000,
                                           "Allow at least one iteration; 200 is the default");
  o.solve.decrement_tolerance =
      config.GetDoubleIn("decrement_tolerance", o.solve.decrement_tolerance, 0, 1e6,
                         "A small non-negative cost decrease, e.g. 1e-10");
  const RobustLossOption loss = ReadRobustLossOption(config);
  o.loss = loss.kind;
  o.loss_scale = loss.scale_mm;
  return std::make_unique<NormalLm>(o);
}

}  // namespace
}  // namespace cellmetry::normal_lm

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.name = "normal_lm";
  info.description =
      "Levenberg-Marquardt on normal equations summed per block (few parameters, many blocks)";
  info.options = {
      {"max_iterations", "", "200", "iteration limit (accepted and rejected steps)"},
      {"decrement_tolerance", "", "1e-10",
       "stop when the Gauss-Newton step would lower the whitened cost by less"},
      {"loss", "", "none", "robust loss: none, huber or cauchy"},
      {"loss_scale", "mm", "1", "residual size where the robust loss starts to bend"},
  };
  registry->AddSolver(info, &cellmetry::normal_lm::Create);
}
