// SolveByReweighting: a Problem's robust cost minimized from a start close to its answer.
//
// Iteratively reweighted least squares (Holland & Welsch 1977, "Robust regression using
// iteratively reweighted least-squares", Commun. Statist. A6(9)) as damped Gauss-Newton on the
// normal equations (Problem::EvaluateNormalEquations): each block weighed by rho'(|r_b|^2) of
// its loss, the step solving (H + lambda diag H) dx = -g, kept where the robust cost falls
// (Marquardt's damping then shrinks) and retried with more damping where it does not. Its fixed
// point is where the robust cost's gradient vanishes, the same answer a trust-region solver
// reaches there.
//
// What it is for: a robust fit started at a least-squares answer, whose verdicts (which rows are
// gross errors) are what is used, never its parameters' last digits (robust_first_fit.h). It
// stops when the step's predicted decrease of the cost, -1/2 g.dx, is below
// `decrement_tolerance`: in a whitened cost that is every free parameter within
// sqrt(2 * tolerance) of its sigma of the stationary point (0.014 sigma at the default). A
// general solver (a job's `solver:`) is the solver plugins' job: this one has no bounds beyond
// clamping a step into them, and trusts its start.
#pragma once

#include "cellmetry/estimation/problem.h"
#include "cellmetry/estimation/solver.h"

namespace cellmetry {

struct ReweightedSolveOptions {
  int max_iterations = 50;             // accepted and rejected steps together
  double decrement_tolerance = 1e-4;   // stop when -1/2 g.dx falls below (cost units)
  double initial_damping = 1e-8;       // lambda, relative to the Hessian's diagonal
};

// Moves the free parameters of `problem` to a minimum of its robust cost (its losses as Build()
// set them) and leaves them there. `converged` is false when it ran out of iterations or the
// damping grew without a step that lowers the cost; `final_cost` is not finite when an
// evaluation failed at the start.
SolverSummary SolveByReweighting(Problem* problem, const ReweightedSolveOptions& options = {});

}  // namespace cellmetry
