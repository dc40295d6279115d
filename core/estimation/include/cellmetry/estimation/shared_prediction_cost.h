// SharedPredictionCost: a residual block that compares one prediction with one measurement,
// where many blocks predict the same thing (the ten captures of one robot pose seen by one
// camera; every world-tag observation of one static camera).
//
// The residual is split in two:
//
//   prediction = Predict(x)       a pose, with A = d(tangent of the prediction) / dx
//   r = Compare(prediction)       3 whitened rows, with D = dr / d(tangent)   (3 x 3)
//
// so the block's Jacobian is D A. Blocks whose costs return the same prediction_key() over the
// same parameter blocks share Predict: the Problem evaluates it once for all of them and sums
// their rows as A^T (sum_i D_i^T W_i D_i) A (src/normal_equations_evaluator.h), each with its
// own robust loss, which is the same sum as block by block in another order. What the "tangent"
// is belongs to the cost (a position's 3 coordinates; a rotation's small-angle vector), provided
// Compare's D and Predict's A agree on it. Evaluate() is the plain block for everything else
// (Ceres).
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <vector>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

class SharedPredictionCost : public ceres::CostFunction {
 public:
  SharedPredictionCost() { set_num_residuals(3); }

  // Costs with the same key (not null) over the same parameter blocks predict the same.
  virtual const void* prediction_key() const = 0;

  // The prediction at `parameters` and, per parameter block whose pointer is not null (or none
  // when `tangent_jacobians` is), d tangent / d block: 3 x the block's size, row-major. False if
  // it cannot be evaluated there.
  virtual bool Predict(double const* const* parameters, Pose* prediction,
                       double** tangent_jacobians) const = 0;

  // This block's residual (3) at `prediction` and, when not null, dr / d tangent.
  virtual void Compare(const Pose& prediction, double* residual,
                       Eigen::Matrix3d* d_residual) const = 0;

  // Whether Compare is affine in the tangent with a constant diagonal D: r = weight .* (tangent -
  // measured), as a position compared with a measured one is (a rotation's error is not). Then
  // the blocks of a unit sum into 3 rows with the same cost up to a constant
  // (summed_position_group.h), and `weight` and `measured` say how. The default: not affine.
  virtual bool AffineComparison(Eigen::Vector3d* weight, Eigen::Vector3d* measured) const {
    (void)weight;
    (void)measured;
    return false;
  }

  // Predict, Compare and D A. A cost may override it with the same in fewer steps.
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // rows = D A for one parameter block of `size` entries, both 3 x size row-major; `rows` may
  // be `tangent` itself (each column is read before it is written).
  static void ChainTangent(const Eigen::Matrix3d& d_residual, const double* tangent, int size,
                           double* rows);
  // ChainTangent in place for every block whose pointer is not null: each block's tangent
  // Jacobian in `jacobians` (3 x its size in `sizes`) becomes D A.
  static void ChainTangentsInPlace(const Eigen::Matrix3d& d_residual,
                                   const std::vector<int32_t>& sizes, double** jacobians);
};

}  // namespace cellmetry
