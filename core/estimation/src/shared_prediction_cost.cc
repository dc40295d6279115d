// SharedPredictionCost::Evaluate (shared_prediction_cost.h): one block on its own.
#include "cellmetry/estimation/shared_prediction_cost.h"

namespace cellmetry {

bool SharedPredictionCost::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  Pose prediction;
  // Predict writes A into the Jacobians' own storage (the same 3 x size shape); each becomes
  // D A in place (Eigen's product goes through a temporary, so the aliasing is safe).
  if (!Predict(parameters, &prediction, jacobians)) return false;
  Eigen::Matrix3d d_residual;
  Compare(prediction, residuals, jacobians ? &d_residual : nullptr);
  if (jacobians == nullptr) return true;
  const std::vector<int32_t>& sizes = parameter_block_sizes();
  for (size_t k = 0; k < sizes.size(); ++k) {
    if (jacobians[k] == nullptr) continue;
    Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> J(jacobians[k], 3,
                                                                           sizes[k]);
    J = d_residual * J;
  }
  return true;
}

}  // namespace cellmetry
