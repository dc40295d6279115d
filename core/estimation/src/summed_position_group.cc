// SummedPositionGroup (summed_position_group.h).
#include "summed_position_group.h"

#include <stdexcept>

namespace cellmetry {

SummedPositionGroup::SummedPositionGroup(std::vector<const SharedPredictionCost*> members)
    : first_(members.front()) {
  set_num_residuals(3);
  *mutable_parameter_block_sizes() = first_->parameter_block_sizes();
  std::vector<Eigen::Vector3d> weights(members.size()), measured(members.size());
  Eigen::Vector3d weight_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d weighted_measured = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < members.size(); ++i) {
    if (!members[i]->AffineComparison(&weights[i], &measured[i])) {
      throw std::logic_error("SummedPositionGroup: a member's comparison is not affine");
    }
    const Eigen::Vector3d w2 = weights[i].cwiseAbs2();
    weight_sum += w2;
    weighted_measured += w2.cwiseProduct(measured[i]);
  }
  mean_ = weighted_measured.cwiseQuotient(weight_sum);
  sqrt_weight_ = weight_sum.cwiseSqrt();
  // The scatter about the mean, summed directly (not as a difference of large sums).
  for (size_t i = 0; i < members.size(); ++i) {
    constant_squared_norm_ += (weights[i].cwiseProduct(measured[i] - mean_)).squaredNorm();
  }
}

bool SummedPositionGroup::Evaluate(double const* const* parameters, double* residuals,
                                   double** jacobians) const {
  Pose prediction;
  // Predict writes the position's Jacobian A (3 x size, row-major) where the rows go; each
  // becomes sqrt(W) A in place.
  if (!first_->Predict(parameters, &prediction, jacobians)) return false;
  Eigen::Map<Eigen::Vector3d> r(residuals);
  r = sqrt_weight_.cwiseProduct(prediction.t - mean_);
  if (jacobians == nullptr) return true;
  const Eigen::Matrix3d d_residual = sqrt_weight_.asDiagonal();
  const std::vector<int32_t>& sizes = parameter_block_sizes();
  for (size_t k = 0; k < sizes.size(); ++k) {
    if (jacobians[k] == nullptr) continue;
    SharedPredictionCost::ChainTangent(d_residual, jacobians[k], sizes[k], jacobians[k]);
  }
  return true;
}

}  // namespace cellmetry
