// The statistical and systematic parts of a cell's uncertainty (internal to the cell layer;
// robust_covariance.h says the estimators).
//
//   statistical  the larger of the chi-square-scaled model sigma and the cluster-robust one with
//                a pose as the cluster (every camera's view of one pose may share errors: the
//                arm's own repeatability, a board seen at that angle), the poses in capture
//                order with the errors their neighbours share (a camera sweeping over a board
//                errs alike at the next pose: SerialClusterRobustCovariance);
//   systematic   with two or more static cameras, each camera left out in turn and the cell's
//                answer moved by one Gauss-Newton step without it (the linearized jackknife:
//                no refits); what the spread of those answers exceeds the statistical part by
//                is error shared by everything one camera measured.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/estimation/estimation_quality.h"
#include "cellmetry/estimation/solver.h"

namespace cellmetry {

// The pose of each residual block of `assembled`'s problem (its block order) as its rank in
// capture order (the first sample that shows it), so that neighbouring clusters are
// neighbouring views; -1 for priors (clusters of their own).
std::vector<int> PoseClustersInCaptureOrder(const AssembledWorkcell& assembled);

// Each residual block's camera as its index in `cameras` (the problem's block order); -1 for
// priors and cameras not listed (kept in every estimate).
std::vector<int> CameraGroups(const AssembledWorkcell& assembled,
                              const std::vector<std::string>& cameras);

// `at` is the fitted problem's linearization at `answer`, from which `u` was computed.
void SplitUncertainty(const WorkcellProblem& spec, const Recording& recording,
                      const AssembledWorkcell& fitted, const Linearization& at, Uncertainty* u);

}  // namespace cellmetry
