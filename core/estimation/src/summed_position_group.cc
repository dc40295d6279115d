// SummedPositionGroup (summed_position_group.h).
#include "summed_position_group.h"

namespace cellmetry {

std::unique_ptr<SummedPositionGroup> SummedPositionGroup::Make(
    const std::vector<const SharedPredictionCost*>& members) {
  std::vector<Eigen::Vector3d> weights(members.size()), measured(members.size());
  Eigen::Vector3d weight_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d weighted_measured = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < members.size(); ++i) {
    if (!members[i]->AffineComparison(&weights[i], &measured[i])) return nullptr;
    const Eigen::Vector3d w2 = weights[i].cwiseAbs2();
    weight_sum += w2;
    weighted_measured += w2.cwiseProduct(measured[i]);
  }
  if (members.empty() || !(weight_sum.array() > 0.0).all()) return nullptr;
  const Eigen::Vector3d mean = weighted_measured.cwiseQuotient(weight_sum);
  // The scatter about the mean, summed directly (not as a difference of large sums).
  double constant_squared_norm = 0.0;
  for (size_t i = 0; i < members.size(); ++i) {
    constant_squared_norm += (weights[i].cwiseProduct(measured[i] - mean)).squaredNorm();
  }
  return std::unique_ptr<SummedPositionGroup>(
      new SummedPositionGroup(members.front(), weight_sum, mean, constant_squared_norm));
}

SummedPositionGroup::SummedPositionGroup(const SharedPredictionCost* first,
                                         const Eigen::Vector3d& weight_sum,
                                         const Eigen::Vector3d& mean, double constant_squared_norm)
    : first_(first), sqrt_weight_(weight_sum.cwiseSqrt()), mean_(mean),
      constant_squared_norm_(constant_squared_norm) {
  set_num_residuals(3);
  *mutable_parameter_block_sizes() = first_->parameter_block_sizes();
}

bool SummedPositionGroup::Evaluate(double const* const* parameters, double* residuals,
                                   double** jacobians) const {
  Pose prediction;
  // Predict writes the position's Jacobian A (3 x size, row-major) where the rows go; each
  // becomes sqrt(W) A in place.
  if (!first_->Predict(parameters, &prediction, jacobians)) return false;
  Eigen::Map<Eigen::Vector3d> r(residuals);
  r = sqrt_weight_.cwiseProduct(prediction.t - mean_);
  if (jacobians != nullptr) {
    SharedPredictionCost::ChainTangentsInPlace(sqrt_weight_.asDiagonal().toDenseMatrix(),
                                               parameter_block_sizes(), jacobians);
  }
  return true;
}

}  // namespace cellmetry
