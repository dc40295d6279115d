// LeavingOneCore (solver.h): the job's solvers, a core left to the caller's other work.
#include "cellmetry/estimation/solver.h"

#include <algorithm>
#include <thread>
#include <utility>

namespace cellmetry {

SolverMaker LeavingOneCore(SolverMaker make) {
  const int cores = static_cast<int>(std::thread::hardware_concurrency());  // 0: unknown
  const int threads = std::max(1, cores - 1);
  return [make = std::move(make), threads] {
    std::unique_ptr<Solver> solver = make();
    solver->LimitThreads(threads);
    return solver;
  };
}

}  // namespace cellmetry
