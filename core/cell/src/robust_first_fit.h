// The robust first fit (internal to the cell layer): where the outlier test (outliers.h) looks
// for gross errors before the plain least-squares fit that the result reports.
//
// A plain fit is pulled by gross errors: with +20 mm on 10 % of the poses it moves so far that
// every residual grows and the outliers hide in the inflated scale. This fit is not. The cell
// is solved by least squares from the closed-form start, then again, warm, with a Cauchy loss
// on each measurement block's whitened norm that bends at `cauchy_width` robust standard
// deviations of the block's group (camera, target, kind) at that first answer: the scale of
// RobustScales, a median, which gross errors in a minority of rows barely move even where they
// pulled the fit. A row 20 robust sigma out then weighs 1 / (1 + (20 / 3)^2) = 0.02 of an
// inlier. (Measured on the simulated UR3 cell of test_outliers: one Cauchy solve suffices from
// 2 mm to 100 mm errors on up to 25 % of the poses, each found with no false alarm and nothing
// moved by more than 0.8 clean sigma. Re-measuring the scale and solving again until it settled
// changed nothing there, and on exp_a did not settle within four solves: 1.5 s, more than the
// whole plain identification. The Cauchy solve straight from the closed form took 200
// iterations on exp_a; after least squares it takes about 10.)
//
// The fit is always Cartesian (the test is on camera-frame rows whatever the job's residual
// form) and is used for nothing but the test: its answer and sigma are dropped. The least-squares
// solve is the job's solver's, and is kept (fit_once.h, LeastSquaresFit): for a Cartesian job
// with nothing to leave out it is the plain fit, which then is not solved twice. The Cauchy
// solve from there is the core's reweighted Gauss-Newton (reweighted_solve.h), stopped within
// 0.014 sigma of its answer: the job's solver would go on to 1e-14 of the cost for digits the
// verdicts never read (on exp_a, Ceres took 13 iterations and half the identification; the
// reweighted solve 6 cheap ones, 23 ms), and the parameters the least-squares fit held stay
// held. The outlier verdicts were unchanged on every test and VSB job. Where it does not settle
// within its 200 iterations (least squares left far off by a gross error, e.g. a delta
// arm's point 5 m away), the job's solver finishes the Cauchy solve from there, as before.
#pragma once

#include <functional>
#include <vector>

#include "cellmetry/cell/workcell.h"
#include "fit_once.h"

namespace cellmetry {

struct RobustFirstFitOptions {
  double cauchy_width = 3.0;  // the loss bends at this many robust sigma of the block's group
  double alpha = 0.01;        // the outlier test's (outliers.h)
  // Called with the least-squares fit once its data, noise and start are known, before it is
  // assembled, then at its answer, before the Cauchy step changes its problem's loss and values
  // (what it reads of the problem it must read then); neither where that fit is not kept
  // (RobustFirstFit::least_squares), the second not where the fit ends before its answer.
  // The first returns whether it started work on another thread that runs beside the solve:
  // the solve then leaves a core to it (LeavingOneCore).
  std::function<bool(LeastSquaresFit*)> at_least_squares_start;
  std::function<void(LeastSquaresFit*)> at_least_squares_answer;
};

struct RobustFirstFit {
  // The rows of the recording that fail the outlier test at the robust fit's answer.
  std::vector<Outlier> outliers;
  // The least-squares fit it started from, at that fit's answer with no loss (as
  // SolveHoldingUnidentifiable left it); null when the job's residual is not Cartesian (the
  // plain fit is another problem then) or nothing was solved.
  std::unique_ptr<LeastSquaresFit> least_squares;
};

// The robust first fit of `recording`. No outliers when the data are too few to fit (the plain
// fit says so) or a solve fails (noted; the plain fit's own test still runs).
RobustFirstFit FindOutliersByRobustFit(const WorkcellProblem& spec, const Recording& recording,
                                       const SolverMaker& make_solver,
                                       const RobustFirstFitOptions& options = {});

}  // namespace cellmetry
