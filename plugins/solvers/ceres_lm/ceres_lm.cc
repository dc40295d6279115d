// `ceres_lm`: Levenberg-Marquardt by Ceres Solver on the assembled problem, directly.
//
// Options (defaults): max_iterations 200; function_tolerance 1e-14; gradient_tolerance 1e-14;
// parameter_tolerance 1e-12; loss none|huber|cauchy; loss_scale 1 (in the measurement's unit,
// mm for positions: residuals beyond it are down-weighted); threads 2;
// linear_solver sparse_normal_cholesky|dense_normal_cholesky|dense_qr. Fewer threads than
// `threads` where the caller limits them (Solver::LimitThreads: it runs other work meanwhile).
#include <chrono>

#include "cellmetry/estimation/problem.h"
#include "cellmetry/estimation/robust_loss_option.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry::ceres_lm {
namespace {

struct Options {
  int max_iterations = 200;
  double function_tolerance = 1e-14;
  double gradient_tolerance = 1e-14;
  double parameter_tolerance = 1e-12;
  RobustLossKind loss = RobustLossKind::kNone;
  double loss_scale = 1.0;
  int threads = 2;
  ceres::LinearSolverType linear_solver = ceres::SPARSE_NORMAL_CHOLESKY;
};

class CeresLm : public Solver {
 public:
  explicit CeresLm(Options options) : options_(options) {}

  SolverSummary Solve(Problem& problem) override {
    const auto start = std::chrono::steady_clock::now();
    if (options_.loss != RobustLossKind::kNone) {
      problem.SetRobustLoss(options_.loss, options_.loss_scale);
      problem.Build();
    }
    SolverSummary summary;
    summary.solver = "ceres_lm";
    if (problem.num_free() == 0) {
      problem.Evaluate(&summary.initial_cost, nullptr, nullptr);
      summary.final_cost = summary.initial_cost;
      summary.converged = true;
      summary.stop_reason = "nothing to solve: no free parameter";
      return summary;
    }
    ceres::Solver::Options o;
    o.minimizer_type = ceres::TRUST_REGION;
    o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    o.linear_solver_type = options_.linear_solver;
    o.max_num_iterations = options_.max_iterations;
    o.function_tolerance = options_.function_tolerance;
    o.gradient_tolerance = options_.gradient_tolerance;
    o.parameter_tolerance = options_.parameter_tolerance;
    o.num_threads = ThreadsWithinLimit(options_.threads);
    o.logging_type = ceres::SILENT;
    ceres::Solver::Summary s;
    // The Problem's Ceres view to solve: the same steps and costs over fewer rows (a pose's
    // captures of one position summed exactly, problem.h).
    ceres::Solve(o, &problem.ceres_problem_for_solving(), &s);
    summary.iterations = static_cast<int>(s.iterations.size()) - 1;
    summary.evaluations = s.num_residual_evaluations;
    summary.initial_cost = s.initial_cost;
    summary.final_cost = s.final_cost;
    summary.converged = s.termination_type == ceres::CONVERGENCE;
    summary.stop_reason = s.message;
    summary.time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  }

 private:
  Options options_;
};

std::unique_ptr<Solver> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "max_iterations", "function_tolerance", "gradient_tolerance",
                     "parameter_tolerance", "loss", "loss_scale", "threads", "linear_solver"});
  Options o;
  o.max_iterations = config.GetIntIn("max_iterations", o.max_iterations, 1, 1000000,
                                     "Allow at least one iteration; 200 is the default");
  // Ceres refuses a negative tolerance or thread count only inside Solve ("Invalid
  // configuration"), after which the fit is the start, reported as an answer: refused here.
  const std::string tolerance_hint = "A tolerance is a small non-negative number, e.g. 1e-14";
  o.function_tolerance =
      config.GetDoubleIn("function_tolerance", o.function_tolerance, 0, 1, tolerance_hint);
  o.gradient_tolerance =
      config.GetDoubleIn("gradient_tolerance", o.gradient_tolerance, 0, 1, tolerance_hint);
  o.parameter_tolerance =
      config.GetDoubleIn("parameter_tolerance", o.parameter_tolerance, 0, 1, tolerance_hint);
  o.threads =
      config.GetIntIn("threads", o.threads, 1, 1024, "Use 1 or more threads; 2 is the default");
  const RobustLossOption loss = ReadRobustLossOption(config);
  o.loss = loss.kind;
  o.loss_scale = loss.scale_mm;
  const std::string linear = config.GetString("linear_solver", "sparse_normal_cholesky");
  if (linear == "dense_normal_cholesky") {
    o.linear_solver = ceres::DENSE_NORMAL_CHOLESKY;
  } else if (linear == "sparse_normal_cholesky") {
    o.linear_solver = ceres::SPARSE_NORMAL_CHOLESKY;
  } else if (linear == "dense_qr") {
    o.linear_solver = ceres::DENSE_QR;
  } else {
    throw config["linear_solver"].Error("unknown linear solver '" + linear + "'",
                                        "Use dense_qr, dense_normal_cholesky or "
                                        "sparse_normal_cholesky");
  }
  return std::make_unique<CeresLm>(o);
}

}  // namespace
}  // namespace cellmetry::ceres_lm

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.name = "ceres_lm";
  info.description = "Levenberg-Marquardt (Ceres Solver), optional robust loss";
  info.options = {
      {"max_iterations", "", "200", "iteration limit"},
      {"function_tolerance", "", "1e-14", "stop when the relative cost change is below"},
      {"gradient_tolerance", "", "1e-14", "stop when the scaled gradient is below"},
      {"parameter_tolerance", "", "1e-12", "stop when the relative step is below"},
      {"loss", "", "none", "robust loss: none, huber or cauchy"},
      {"loss_scale", "mm", "1", "residual size where the robust loss starts to bend"},
      {"threads", "", "2", "threads for residual evaluation"},
      {"linear_solver", "", "sparse_normal_cholesky",
       "sparse_normal_cholesky, dense_normal_cholesky or dense_qr"},
  };
  registry->AddSolver(info, &cellmetry::ceres_lm::Create);
}
