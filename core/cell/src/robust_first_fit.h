// The robust first fit (internal to the cell layer): where the outlier test (outliers.h) looks
// for gross errors before the plain least-squares fit that the result reports.
//
// A plain fit is pulled by gross errors: with +20 mm on 10 % of the poses it moves so far that
// every residual grows and the outliers hide in the inflated scale. This fit is not: the cell
// is solved with a Cauchy loss on each measurement block's whitened norm, bending at
// kCauchyWidth robust standard deviations of the block's group (camera, target, kind; the
// scale of RobustScales, a median, which 10 % of gross errors barely move). The scale is
// measured again at each answer and the cell solved again, warm, until no group's scale changes
// by more than 5 % (at most kRounds solves): the first solve starts from the closed form, whose
// residuals are wide, and narrows the loss as the answer improves (graduated non-convexity).
// The Cauchy loss gives a row 20 robust sigma out a weight of 1 / (1 + (20 / 3)^2) = 0.02.
//
// The fit is always Cartesian (the test is on camera-frame rows whatever the job's residual
// form) and is used for nothing but the test: its answer and sigma are dropped.
#pragma once

#include <vector>

#include "cellmetry/cell/workcell.h"

namespace cellmetry {

struct RobustFirstFitOptions {
  double cauchy_width = 3.0;  // the loss bends at this many robust sigma of the block's group
  int max_rounds = 4;         // solves at most, each with the scale of the previous answer
  double alpha = 0.01;        // the outlier test's (outliers.h)
};

// The rows of `recording` that fail the outlier test at the robust first fit's answer. None
// when the data are too few to fit (the plain fit says so) or the robust solve fails (noted;
// the plain fit's own test still runs).
std::vector<Outlier> FindOutliersByRobustFit(const WorkcellProblem& spec,
                                             const Recording& recording,
                                             const SolverMaker& make_solver,
                                             const RobustFirstFitOptions& options = {});

}  // namespace cellmetry
