// A fitted cell's residual rows (internal to the cell layer): one row per measurement block,
// in the measurement's units (mm / rad) and whitened, in the Problem's block order (the
// measurement blocks come before any prior). What the residual statistics, the unknown-sigma
// estimate and the outlier test (outliers.h) read.
#pragma once

#include <vector>

#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_result.h"

namespace cellmetry {

// The whitened residuals of every block (priors too) at the problem's current values, without
// the robust loss (NaN throughout where a cost function fails). `at`: a valid linearization made
// at those values (a solve's last identifiability check), whose residuals are taken instead of
// evaluated again.
Eigen::VectorXd WhitenedResiduals(Problem& problem, const Linearization* at = nullptr);

// The rows at the problem's current values, without the robust loss (NaN where a cost function
// fails); `at` as for WhitenedResiduals.
std::vector<ResidualRow> ResidualRows(AssembledWorkcell& assembled,
                                      const Linearization* at = nullptr);

}  // namespace cellmetry
