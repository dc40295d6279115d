// SharedPredictionGroup (internal to the estimation layer): the blocks of one prediction unit
// (shared_prediction_cost.h) as one Ceres residual block.
//
// Ceres evaluates each residual block on its own, so ten captures of one pose seen by one
// camera cost it ten chains, ten Jacobian hand-overs and ten validity checks per iteration. Given
// to Ceres as one block of 3 x n rows, the chain is evaluated once and each capture adds only its
// comparison: r_i = Compare_i(Predict(x)), J_i = D_i A. The rows, their Jacobian and therefore
// 0.5 |r|^2 are those of the n blocks; only their order in Ceres's Jacobian differs, which
// Problem::Evaluate (ceres_adapter.h) undoes.
//
// A unit (up to 256 members, evaluation_layout.h) is given in pieces of at most 64 members
// (ceres_adapter.cc): Ceres evaluates each block on one thread, and a static camera's world-tag
// units of 256 views, 768 rows each, left its two threads unevenly loaded.
//
// Only where no member carries a robust loss: Ceres applies a loss to a block's whole squared
// norm, and each capture's loss must see its own (the robust fit's Cauchy loss is per capture).
#pragma once

#include <ceres/cost_function.h>

#include <vector>

#include "cellmetry/estimation/shared_prediction_cost.h"

namespace cellmetry {

class SharedPredictionGroup : public ceres::CostFunction {
 public:
  // `members` share one prediction (the same key over the same parameter blocks); not owned.
  explicit SharedPredictionGroup(std::vector<const SharedPredictionCost*> members);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  std::vector<const SharedPredictionCost*> members_;
};

}  // namespace cellmetry
