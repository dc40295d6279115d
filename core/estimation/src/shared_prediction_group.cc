// SharedPredictionGroup (shared_prediction_group.h).
#include "shared_prediction_group.h"

#include <Eigen/Core>

namespace cellmetry {

SharedPredictionGroup::SharedPredictionGroup(std::vector<const SharedPredictionCost*> members)
    : members_(std::move(members)) {
  set_num_residuals(3 * static_cast<int>(members_.size()));
  *mutable_parameter_block_sizes() = members_.front()->parameter_block_sizes();
}

bool SharedPredictionGroup::Evaluate(double const* const* parameters, double* residuals,
                                     double** jacobians) const {
  Pose prediction;
  // Predict writes each asked block's tangent Jacobian A (3 x size, row-major) into the first
  // three rows of that block's Jacobian; the members' rows D_i A are written from the last
  // member to the first, so the first member's, which overwrite A, come when A is last read.
  if (!members_.front()->Predict(parameters, &prediction, jacobians)) return false;
  const std::vector<int32_t>& sizes = parameter_block_sizes();
  Eigen::Matrix3d d_residual;
  for (int i = static_cast<int>(members_.size()) - 1; i >= 0; --i) {
    members_[i]->Compare(prediction, residuals + 3 * i, jacobians ? &d_residual : nullptr);
    if (jacobians == nullptr) continue;
    for (size_t k = 0; k < sizes.size(); ++k) {
      if (jacobians[k] == nullptr) continue;
      SharedPredictionCost::ChainTangent(d_residual, jacobians[k], sizes[k],
                                         jacobians[k] + 3 * i * sizes[k]);
    }
  }
  return true;
}

}  // namespace cellmetry
