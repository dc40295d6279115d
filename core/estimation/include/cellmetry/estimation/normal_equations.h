// NormalEquations: the Gauss-Newton normal equations of a problem's robust cost at its current
// values (Problem::EvaluateNormalEquations), over its free parameters:
//
//   cost     = 1/2 sum_b rho_b(s_b),   s_b = |r_b|^2
//   gradient = sum_b w_b J_b^T r_b
//   hessian  = sum_b J_b^T (w_b I + c_b r_b r_b^T) J_b
//
// for each residual block b, w_b = rho_b'(s_b) and c_b = 2 rho_b''(s_b) of its robust loss rho_b
// (the identity where it has none: w_b = 1, c_b = 0, and the hessian is J^T J). c_b is 0 where
// w_b + c_b s_b <= 0 (a block far out on a redescending loss), so the hessian stays positive
// semi-definite (Triggs et al. 2000, "Bundle adjustment: a modern synthesis", sec. 4.3; Ceres
// keeps the term only where rho'' > 0, which a Cauchy or Huber loss never has: with it the
// reweighted solve of exp_a takes 6 iterations instead of 8).
#pragma once

#include <Eigen/Core>

namespace cellmetry {

struct NormalEquations {
  double cost = 0.0;
  Eigen::VectorXd gradient;
  Eigen::MatrixXd hessian;
};

}  // namespace cellmetry
