// SharedPredictionCost::Evaluate (shared_prediction_cost.h): one block on its own.
#include "cellmetry/estimation/shared_prediction_cost.h"

namespace cellmetry {

bool SharedPredictionCost::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  Pose prediction;
  // Predict writes A into the Jacobians' own storage (the same 3 x size shape, row-major); each
  // column becomes D times itself in place (fixed-size: no temporary on the heap per block).
  if (!Predict(parameters, &prediction, jacobians)) return false;
  Eigen::Matrix3d d_residual;
  Compare(prediction, residuals, jacobians ? &d_residual : nullptr);
  if (jacobians != nullptr) ChainTangentsInPlace(d_residual, parameter_block_sizes(), jacobians);
  return true;
}

void SharedPredictionCost::ChainTangentsInPlace(const Eigen::Matrix3d& d_residual,
                                                const std::vector<int32_t>& sizes,
                                                double** jacobians) {
  for (size_t k = 0; k < sizes.size(); ++k) {
    if (jacobians[k] != nullptr) ChainTangent(d_residual, jacobians[k], sizes[k], jacobians[k]);
  }
}

void SharedPredictionCost::ChainTangent(const Eigen::Matrix3d& d_residual, const double* tangent,
                                        int size, double* rows) {
  for (int j = 0; j < size; ++j) {
    const Eigen::Vector3d a(tangent[j], tangent[size + j], tangent[2 * size + j]);
    const Eigen::Vector3d column = d_residual * a;
    rows[j] = column[0];
    rows[size + j] = column[1];
    rows[2 * size + j] = column[2];
  }
}

}  // namespace cellmetry
