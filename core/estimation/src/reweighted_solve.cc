// SolveByReweighting (reweighted_solve.h): damped Gauss-Newton on reweighted normal equations.
#include "cellmetry/estimation/reweighted_solve.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

namespace cellmetry {
namespace {

// The damped step (H + lambda diag H) dx = -g. A diagonal entry of zero (a column no weighted
// row reaches) is damped as a tiny one would be, and every entry by at least 1e-14 of itself,
// so the system stays definite (lambda 0: the Gauss-Newton step).
Eigen::VectorXd DampedStep(const NormalEquations& at, double lambda) {
  const Eigen::VectorXd diagonal = at.hessian.diagonal();
  const double floor = 1e-12 * std::max(diagonal.maxCoeff(), 1e-300);
  Eigen::MatrixXd damped = at.hessian;
  damped.diagonal() += std::max(lambda, 1e-14) * diagonal.cwiseMax(floor);
  return damped.ldlt().solve(-at.gradient);
}

Eigen::VectorXd Clamp(const Eigen::VectorXd& x, const Eigen::VectorXd& lower,
                      const Eigen::VectorXd& upper) {
  return x.cwiseMax(lower).cwiseMin(upper);
}

std::string Reason(const char* format, double value) {
  char text[160];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace

SolverSummary SolveByReweighting(Problem* problem, const ReweightedSolveOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  SolverSummary summary;
  summary.solver = "reweighted_gauss_newton";
  NormalEquations at;
  ++summary.evaluations;
  if (!problem->EvaluateNormalEquations(&at) || !std::isfinite(at.cost)) {
    summary.initial_cost = summary.final_cost = std::numeric_limits<double>::quiet_NaN();
    summary.stop_reason = "the cost cannot be evaluated at the start";
    return summary;
  }
  summary.initial_cost = at.cost;
  const Eigen::VectorXd lower = problem->LowerBounds(), upper = problem->UpperBounds();
  Eigen::VectorXd x = problem->FreeValues();
  double lambda = options.initial_damping;
  summary.stop_reason = "iteration limit reached";
  if (problem->num_free() == 0) {
    summary.converged = true;
    summary.stop_reason = "nothing to solve: no free parameter";
  }
  for (int iteration = 0; iteration < options.max_iterations && !summary.converged; ++iteration) {
    // Converged by the Gauss-Newton step's decrease, not the damped one's: after rejected
    // steps the damping shrinks the step, and with it the decrease, far from the answer. A
    // decrease below 1e-13 of the cost is below what the cost's sum resolves (tens of thousands
    // of terms, each rounded): no trial could show it, so that is converged too.
    const Eigen::VectorXd newton_step = DampedStep(at, 0.0);
    const double decrement = -0.5 * at.gradient.dot(newton_step);
    const double tolerance = std::max(options.decrement_tolerance, 1e-13 * std::abs(at.cost));
    if (std::isfinite(decrement) && decrement < tolerance) {
      summary.converged = true;
      summary.stop_reason = Reason("predicted cost decrease %.2g below the tolerance", decrement);
      break;
    }
    const Eigen::VectorXd trial = Clamp(x + DampedStep(at, lambda), lower, upper);
    problem->SetFreeValues(trial);
    NormalEquations at_trial;
    ++summary.evaluations;
    ++summary.iterations;
    if (problem->EvaluateNormalEquations(&at_trial) && at_trial.cost < at.cost) {
      x = trial;
      at = std::move(at_trial);
      lambda = std::max(lambda / 10.0, 1e-12);
      continue;
    }
    problem->SetFreeValues(x);
    lambda *= 10.0;
    if (lambda > 1e8) {
      summary.stop_reason = "no step lowers the cost (damping 1e8)";
      break;
    }
  }
  summary.final_cost = at.cost;
  summary.time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return summary;
}

SolverMaker ReweightedSolver(const ReweightedSolveOptions& options) {
  class Reweighted : public Solver {
   public:
    explicit Reweighted(const ReweightedSolveOptions& options) : options_(options) {}
    SolverSummary Solve(Problem& problem) override {
      return SolveByReweighting(&problem, options_);
    }

   private:
    ReweightedSolveOptions options_;
  };
  return [options] { return std::make_unique<Reweighted>(options); };
}

}  // namespace cellmetry
