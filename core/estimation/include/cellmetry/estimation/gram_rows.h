// GramRows: rows with a Jacobian's Gram matrix J^T J, a tenth of J's rows where repeated
// captures share a prediction, for everything that needs J only through J^T J (its R factor,
// column norms and their groups: identifiability, the covariance, the camera jackknife).
//
// A unit of blocks sharing one prediction (shared_prediction_cost.h) has rows D_i A: the
// prediction's tangent Jacobian A (3 x its columns) times each comparison's D_i (3 x 3). Their
// Gram matrix is A^T (sum_i D_i^T D_i) A = (L^T A)^T (L^T A), with L L^T = sum_i D_i^T D_i, so
// the unit's 3 rows L^T A stand for all of its rows; every other block's rows stand for
// themselves. RFactor of these rows is J's up to the signs of R's rows (r_factor.h), on exp_a
// from 67,500 rows to about 4,500. Orthogonal but for the 3 x 3 Cholesky of each unit's sum,
// whose D_i are the comparisons' (1 / sigma, times J_l^-1 for a rotation): well conditioned,
// so the R factor keeps a dense QR's accuracy (test_r_factor). Made only where they are at most
// a quarter of J's rows (Problem::EvaluateSparse); elsewhere J serves as it is.
#pragma once

#include <vector>

#include "cellmetry/estimation/r_factor.h"

namespace cellmetry {

struct GramRows {
  SparseJacobian rows;            // J's columns
  std::vector<int> block;         // per row, the residual block it stands for (its unit's first)
  std::vector<int> row_of_block;  // per residual block, the first row that stands for it
};

}  // namespace cellmetry
