// Solver: the contract of a solver plugin.
//
// A solver gets one assembled Problem (problem.h), moves its free parameters to a minimum of
// 0.5 * |r(x)|^2 (residuals are already whitened by the measurement sigma), and says how it went.
// It must leave the Problem's parameter values at its answer. Uncertainty and diagnostics are
// computed by the core afterwards, identically for every solver.
#pragma once

#include <functional>
#include <memory>
#include <string>

namespace cellmetry {

class Problem;

struct SolverSummary {
  std::string solver;            // plugin name
  int iterations = 0;            // outer iterations (LM steps, pinv steps, NLopt evaluations)
  int evaluations = 0;           // residual evaluations
  double initial_cost = 0.0;     // 0.5 * |r|^2 at the start
  double final_cost = 0.0;       // 0.5 * |r|^2 at the answer
  bool converged = false;        // stopped by a convergence test, not by a limit or a failure
  std::string stop_reason;       // one line, e.g. "relative cost change 3e-12 < 1e-10"
  double time_s = 0.0;           // wall time of Solve()
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual SolverSummary Solve(Problem& problem) = 0;
};

// Makes a fresh solver (the job's); calibrations solve several problems with one job.
using SolverMaker = std::function<std::unique_ptr<Solver>()>;

}  // namespace cellmetry
