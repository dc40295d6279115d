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
  std::string solver;         // plugin name
  int iterations = 0;         // outer iterations (LM steps, pinv steps, NLopt evaluations)
  int evaluations = 0;        // residual evaluations
  double initial_cost = 0.0;  // 0.5 * |r|^2 at the start
  double final_cost = 0.0;    // 0.5 * |r|^2 at the answer
  bool converged = false;     // stopped by a convergence test, not by a limit or a failure
  std::string stop_reason;    // one line, e.g. "relative cost change 3e-12 < 1e-10"
  double time_s = 0.0;        // wall time of Solve()
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual SolverSummary Solve(Problem& problem) = 0;

  // At most `threads` threads in the solves to come (0: as many as the solver's own options
  // say): the caller runs other work on the machine's other cores meanwhile (LeavingOneCore).
  // A solver that does not choose its thread count (one thread, or TBB's) may ignore it.
  void LimitThreads(int threads) { thread_limit_ = threads; }

 protected:
  // `wanted` threads (the solver's option), within the caller's limit.
  int ThreadsWithinLimit(int wanted) const {
    return thread_limit_ > 0 && thread_limit_ < wanted ? thread_limit_ : wanted;
  }

 private:
  int thread_limit_ = 0;
};

// Makes a fresh solver (the job's); calibrations solve several problems with one job.
using SolverMaker = std::function<std::unique_ptr<Solver>()>;

// `make`'s solvers, each limited to the machine's cores but one (at least one thread): for a
// solve the caller runs while its own work on another thread takes a core. On a 2-core
// machine a small cell's Ceres solve is quicker on one thread then than on two that contend
// with that work (docs/benchmarks.md), while a solve alone keeps both.
SolverMaker LeavingOneCore(SolverMaker make);

}  // namespace cellmetry
