// CeresAdapter: a BlockRegistry as ceres::Problems (internal to the estimation layer; Problem's
// ceres_problem(), ceres_problem_for_solving() and Evaluate() are its).
//
// Two views, each built on first use:
//   for evaluation  rows are the registry's rows (in another order): Evaluate() reads them back
//                   in the registry's order, with Ceres's dense evaluation;
//   for solving     the same minimum, steps and reported costs over fewer rows: its residuals
//                   are not the registry's rows.
// Both hold the registry's parameter blocks (the same memory) with the same fixed entries
// (a SubsetManifold; a fully fixed block constant), bounds, and blocks no residual reads left
// out. They differ in how a unit of blocks sharing a prediction (same key, same parameter
// blocks, no robust loss) reaches Ceres:
//   to evaluate  Ceres blocks of its members' rows, 64 members at most each
//                (shared_prediction_group.h);
//   to solve     where every member compares a position affinely, 3 rows summing them exactly
//                (summed_position_group.h), the constant left over a block without parameters,
//                whose cost Ceres adds to the costs it reports; other units as to evaluate.
//
// The views point at the registry's costs and losses, which its Build() makes again: Reset()
// the adapter before every BlockRegistry::Build(). A problem only linearized (the covariance,
// the uncertain inputs) never pays for Ceres's structures.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "cellmetry/estimation/block_registry.h"
#include "evaluation_layout.h"

namespace cellmetry {

class CeresAdapter {
 public:
  CeresAdapter(BlockRegistry* registry, const EvaluationLayout* layout)
      : registry_(*registry), layout_(*layout) {}
  CeresAdapter(const CeresAdapter&) = delete;
  CeresAdapter& operator=(const CeresAdapter&) = delete;

  ceres::Problem& for_evaluation();
  ceres::Problem& for_solving();
  // Residuals (whitened) and, when `jacobian` is not null, the dense Jacobian with respect to the
  // free parameters, at the current values, in the registry's row order. False if a cost
  // function failed.
  bool Evaluate(double* cost, Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian,
                bool apply_loss);
  // Drops both views (made again on next use).
  void Reset();

 private:
  struct View {
    std::vector<ceres::ResidualBlockId> residual_ids;
    // The Ceres blocks made for units (shared_prediction_group.h, summed_position_group.h) and
    // the constant's block, which this view owns; the others are the registry's.
    std::vector<std::unique_ptr<ceres::CostFunction>> unit_costs;
    std::vector<std::unique_ptr<ceres::Manifold>> manifolds;
    std::vector<double*> variable_blocks;
    // The registry's row of each of Ceres's rows (empty: the same order); only for the view to
    // evaluate.
    std::vector<int> rows;
    std::vector<double*> scratch_pointers;    // AddResidual's, kept to spare an allocation
    std::unique_ptr<ceres::Problem> problem;  // last: destroyed first, before what it points to
    void Reset();
  };

  // `summed`: the view to solve (positions summed); else the view to evaluate.
  void Build(bool summed, View* view);
  // Build's residual blocks, units grouped (or summed) where they can be.
  void AddResiduals(bool summed, View* view);
  // Unit u as Ceres blocks; the squared norm of the constant its summing left over (0: none).
  double AddUnit(int u, bool summed, View* view);
  // `cost` over residual block k's parameter blocks into `view`.
  void AddResidual(ceres::CostFunction* cost, ceres::LossFunction* loss, int k, View* view);
  // Build's parameter blocks: fixed entries, bounds, constant blocks.
  void SetParameterBlocks(View* view);

  BlockRegistry& registry_;
  const EvaluationLayout& layout_;
  View for_evaluation_, for_solving_;
};

}  // namespace cellmetry
