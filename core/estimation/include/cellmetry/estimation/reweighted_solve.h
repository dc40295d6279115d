// SolveByReweighting: Levenberg-Marquardt on normal equations, robust where the Problem has losses.
//
// Iteratively reweighted least squares (Holland & Welsch 1977, "Robust regression using
// iteratively reweighted least-squares", Commun. Statist. A6(9)) as damped Gauss-Newton on the
// normal equations (Problem::EvaluateNormalEquations): each block weighed by rho'(|r_b|^2) of
// its loss, the step solving (H + lambda diag H) dx = -g, kept where the robust cost falls
// (Marquardt's damping then shrinks) and retried with more damping where it does not. Its fixed
// point is where the robust cost's gradient vanishes, the same answer a trust-region solver
// reaches there.
//
// Without a loss every weight is 1 and this is Levenberg-Marquardt on the normal equations. It
// stops when the Gauss-Newton step's predicted decrease of the cost, -1/2 g.dx, is below
// `decrement_tolerance` (or 1e-13 of the cost, below which the cost's rounded sum cannot show a
// decrease): in a whitened cost that is every free parameter within sqrt(2 * tolerance) of its
// sigma of the stationary point (0.014 sigma at 1e-4).
//
// Two users. The robust first fit (robust_first_fit.h) starts it at a least-squares answer and
// reads only its verdicts (which rows are gross errors): 1e-4 is plenty. The `normal_lm` solver
// plugin offers it to jobs with a tight tolerance: where a cell has a few dozen free parameters
// and tens of thousands of residual blocks, an iteration on the summed normal equations costs a
// fraction of Ceres's, whose evaluator, Jacobian scaling and sparse J^T J work per block
// (docs/benchmarks.md). Bounds are kept by clamping each step into them (projected steps), which
// suffices for the bounds cells have (none on frames, a few on effects) but is no active-set
// method: a problem living on its bounds wants Ceres.
#pragma once

#include "cellmetry/estimation/problem.h"
#include "cellmetry/estimation/solver.h"

namespace cellmetry {

struct ReweightedSolveOptions {
  int max_iterations = 200;           // accepted and rejected steps together (as ceres_lm)
  double decrement_tolerance = 1e-4;  // stop when -1/2 g.dx falls below (cost units)
  double initial_damping = 1e-8;      // lambda, relative to the Hessian's diagonal: Gauss-Newton
                                      // first, more damping only after a rejected step
};

// Moves the free parameters of `problem` to a minimum of its robust cost (its losses as Build()
// set them) and leaves them there. `converged` is false when it ran out of iterations or the
// damping grew without a step that lowers the cost; `final_cost` is not finite when an
// evaluation failed at the start.
SolverSummary SolveByReweighting(Problem* problem, const ReweightedSolveOptions& options = {});

// The same as a Solver, for solves the core makes for itself whose answer is read only for what
// it implies, never reported (a first fit whose residuals give an unknown sigma): a cell's few
// dozen columns over many blocks take a fraction of a Ceres iteration on the normal equations.
SolverMaker ReweightedSolver(const ReweightedSolveOptions& options = {});

}  // namespace cellmetry
