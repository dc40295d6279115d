// SummedPositionGroup (internal to the estimation layer): the blocks of one prediction unit
// that compare its position with measured ones, summed exactly into one Ceres block of 3 rows.
//
// Each member's residual is r_i = w_i .* (t - y_i): the predicted position t, its measured y_i,
// a diagonal weight w_i (1/sigma). Per axis a, with W_a = sum_i w_ia^2 and the weighted mean
// m_a = sum_i w_ia^2 y_ia / W_a,
//
//   sum_i r_ia^2 = W_a (t_a - m_a)^2 + sum_i w_ia^2 (y_ia - m_a)^2,
//
// (the cross term is 2 (t_a - m_a) sum_i w_ia^2 (m_a - y_ia) = 0), so the 3 rows
// g_a = sqrt(W_a) (t_a - m_a) have the members' J^T J and J^T r at every x, and their cost
// differs from the members' by a constant: `constant_squared_norm()`, which the Problem gives
// Ceres as a block without parameters (Ceres adds it to the costs it reports). A Ceres solve then
// takes the same steps to the same minimum over n times fewer rows: exp_a's ten captures of a
// pose by a camera are 3 rows instead of 30, and a unit of 256 views of the world tag 3 instead
// of 768.
//
// Only for Ceres's solve (Problem::ceres_problem_for_solving): the rows are not the members',
// so residuals read per row (Problem::Evaluate) come from the other Ceres problem. Only where
// no member carries a robust loss (a loss acts on each capture's own norm).
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "cellmetry/estimation/shared_prediction_cost.h"

namespace cellmetry {

class SummedPositionGroup : public ceres::CostFunction {
 public:
  // `members` share one prediction (the same key over the same parameter blocks); not owned.
  // Null where they cannot be summed: one compares it other than affinely
  // (SharedPredictionCost::AffineComparison), or an axis has no weight.
  static std::unique_ptr<SummedPositionGroup> Make(
      const std::vector<const SharedPredictionCost*>& members);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // sum_i |r_i|^2 - |g|^2: the same at every x.
  double constant_squared_norm() const { return constant_squared_norm_; }

 private:
  SummedPositionGroup(const SharedPredictionCost* first, const Eigen::Vector3d& weight_sum,
                      const Eigen::Vector3d& mean, double constant_squared_norm);

  const SharedPredictionCost* first_;  // predicts for all
  Eigen::Vector3d sqrt_weight_;        // sqrt(W_a)
  Eigen::Vector3d mean_;               // m_a
  double constant_squared_norm_ = 0.0;
};

}  // namespace cellmetry
