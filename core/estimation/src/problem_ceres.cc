// Problem's two ceres::Problems (problem.h): one whose rows are Evaluate()'s, one to solve;
// and Evaluate() itself, Ceres's dense evaluation put back in this Problem's row order.
//
// Both hold the Problem's parameter blocks (the same memory) with the same fixed entries, bounds
// and constant blocks. They differ in how a unit of blocks sharing a prediction (same key, same
// parameter blocks, no robust loss) reaches Ceres:
//   to evaluate: Ceres blocks of its members' rows, 64 members at most each
//                (shared_prediction_group.h);
//   to solve:    where every member compares a position affinely, 3 rows summing them exactly
//                (summed_position_group.h), the constant left over a block without parameters;
//                other units as to evaluate.
#include <algorithm>
#include <cmath>
#include <vector>

#include "cellmetry/estimation/problem.h"
#include "cellmetry/estimation/shared_prediction_cost.h"
#include "problem_blocks.h"
#include "shared_prediction_group.h"
#include "summed_position_group.h"

namespace cellmetry {

namespace {

// One row whose square is a constant: the part of the summed units' cost no parameter moves.
// Ceres removes a block without parameters before it iterates and adds its cost to the costs it
// reports, so the solve's reported costs are the Problem's.
class ConstantCost : public ceres::CostFunction {
 public:
  explicit ConstantCost(double squared_norm) : residual_(std::sqrt(squared_norm)) {
    set_num_residuals(1);
  }
  bool Evaluate(double const* const*, double* residuals, double**) const override {
    residuals[0] = residual_;
    return true;
  }

 private:
  double residual_;
};

constexpr size_t kMaxGroupMembers = 64;

}  // namespace

void Problem::CeresView::Reset() {
  problem.reset();
  residual_ids.clear();
  unit_costs.clear();
  manifolds.clear();
  variable_blocks.clear();
  rows.clear();
}

ceres::Problem& Problem::ceres_problem() {
  if (!for_evaluation_.problem) BuildCeres(/*summed=*/false, &for_evaluation_);
  return *for_evaluation_.problem;
}

ceres::Problem& Problem::ceres_problem_for_solving() {
  if (!for_solving_.problem) BuildCeres(/*summed=*/true, &for_solving_);
  return *for_solving_.problem;
}

void Problem::AddCeresResidual(ceres::CostFunction* cost, ceres::LossFunction* loss, int k,
                               CeresView* view) {
  std::vector<double*>& pointers = view->scratch_pointers;
  pointers.clear();
  for (int b : *evaluation_order_[k].second) pointers.push_back(values(b));
  view->residual_ids.push_back(view->problem->AddResidualBlock(cost, loss, pointers));
}

void Problem::AddCeresResiduals(bool summed, CeresView* view) {
  double constant_squared_norm = 0.0;
  for (int u = 0; u < num_predictions(); ++u) {
    const int* first = unit_blocks_.data() + unit_start_[u];
    const int* last = unit_blocks_.data() + unit_start_[u + 1];
    const bool group = SharesPrediction(u) && std::all_of(first, last, [&](int k) {
                         return evaluation_losses_[k] == nullptr;
                       });
    if (!group) {
      for (const int* k = first; k != last; ++k) {
        AddCeresResidual(evaluation_order_[*k].first, evaluation_losses_[*k], *k, view);
      }
    } else {
      std::vector<const SharedPredictionCost*> members;
      for (const int* k = first; k != last; ++k) {
        members.push_back(static_cast<const SharedPredictionCost*>(evaluation_order_[*k].first));
      }
      if (summed) {
        if (auto summed_unit = SummedPositionGroup::Make(members)) {
          constant_squared_norm += summed_unit->constant_squared_norm();
          view->unit_costs.push_back(std::move(summed_unit));
          AddCeresResidual(view->unit_costs.back().get(), nullptr, *first, view);
          continue;  // its rows are none of Evaluate()'s
        }
      }
      // In pieces of at most kMaxGroupMembers: Ceres evaluates a block on one thread, and a
      // static camera's world-tag units are 256 views.
      for (size_t begin = 0; begin < members.size(); begin += kMaxGroupMembers) {
        const size_t end = std::min(members.size(), begin + kMaxGroupMembers);
        view->unit_costs.push_back(std::make_unique<SharedPredictionGroup>(
            std::vector<const SharedPredictionCost*>(members.begin() + begin,
                                                     members.begin() + end)));
        AddCeresResidual(view->unit_costs.back().get(), nullptr, *first, view);
      }
    }
    if (summed) continue;  // the rows' order matters only to Evaluate()
    for (const int* k = first; k != last; ++k) {
      const int rows = evaluation_order_[*k].first->num_residuals();
      for (int row = rows_[*k]; row < rows_[*k] + rows; ++row) view->rows.push_back(row);
    }
  }
  if (constant_squared_norm > 0.0) {
    view->unit_costs.push_back(std::make_unique<ConstantCost>(constant_squared_norm));
    view->residual_ids.push_back(view->problem->AddResidualBlock(
        view->unit_costs.back().get(), nullptr, std::vector<double*>{}));
  }
  // A permutation of the rows is the identity exactly when it is sorted.
  if (std::is_sorted(view->rows.begin(), view->rows.end())) view->rows.clear();
}

void Problem::BuildCeres(bool summed, CeresView* view) {
  view->Reset();
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.enable_fast_removal = false;
  view->problem = std::make_unique<ceres::Problem>(options);
  AddCeresResiduals(summed, view);
  for (size_t b = 0; b < blocks_.size(); ++b) {
    Block& block = *blocks_[b];
    if (!block.used) continue;
    std::vector<int> fixed;
    for (size_t i = 0; i < block.params.size(); ++i) {
      const Parameter& p = block.params[i];
      if (p.fixed) {
        fixed.push_back(static_cast<int>(i));
        continue;
      }
      if (p.lower) view->problem->SetParameterLowerBound(block.values.data(), i, *p.lower);
      if (p.upper) view->problem->SetParameterUpperBound(block.values.data(), i, *p.upper);
    }
    if (fixed.size() == block.params.size()) {
      view->problem->SetParameterBlockConstant(block.values.data());
    } else {
      if (!fixed.empty()) {
        view->manifolds.push_back(std::make_unique<ceres::SubsetManifold>(
            static_cast<int>(block.params.size()), fixed));
        view->problem->SetManifold(block.values.data(), view->manifolds.back().get());
      }
      view->variable_blocks.push_back(block.values.data());
    }
  }
}

namespace {

// Ceres's evaluation of `problem` over `blocks` (every free block, every residual block).
bool EvaluateCeres(ceres::Problem& problem, const std::vector<double*>& parameter_blocks,
                   const std::vector<ceres::ResidualBlockId>& residual_blocks, bool apply_loss,
                   double* cost, Eigen::VectorXd* residuals, ceres::CRSMatrix* crs) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = parameter_blocks;
  options.residual_blocks = residual_blocks;
  options.apply_loss_function = apply_loss;
  options.num_threads = 2;
  double local_cost = 0.0;
  std::vector<double> r;
  if (!problem.Evaluate(options, &local_cost, residuals ? &r : nullptr, nullptr, crs)) {
    return false;
  }
  if (cost) *cost = local_cost;
  if (residuals) *residuals = Eigen::Map<Eigen::VectorXd>(r.data(), r.size());
  return true;
}

}  // namespace

bool Problem::Evaluate(double* cost, Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian,
                       bool apply_loss) {
  ceres::CRSMatrix crs;
  ceres::Problem& ceres = ceres_problem();
  if (!EvaluateCeres(ceres, for_evaluation_.variable_blocks, for_evaluation_.residual_ids,
                     apply_loss, cost, residuals,
                     jacobian ? &crs : nullptr)) {
    return false;
  }
  // Ceres's rows in this Problem's order (BuildCeres: units it evaluates as one block).
  auto row_of = [&](int ceres_row) {
    return for_evaluation_.rows.empty() ? ceres_row : for_evaluation_.rows[ceres_row];
  };
  if (residuals && !for_evaluation_.rows.empty()) {
    Eigen::VectorXd in_order(residuals->size());
    for (int row = 0; row < residuals->size(); ++row) in_order[row_of(row)] = (*residuals)[row];
    *residuals = std::move(in_order);
  }
  if (jacobian) {
    jacobian->setZero(crs.num_rows, crs.num_cols);
    for (int row = 0; row < crs.num_rows; ++row) {
      for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) {
        (*jacobian)(row_of(row), crs.cols[k]) = crs.values[k];
      }
    }
  }
  return true;
}

}  // namespace cellmetry
