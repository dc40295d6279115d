// CeresAdapter (ceres_adapter.h): the two ceres::Problem views of a registry, and Ceres's dense
// evaluation put back in the registry's row order.
#include "ceres_adapter.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "cellmetry/estimation/shared_prediction_cost.h"
#include "evaluation_layout.h"
#include "shared_prediction_group.h"
#include "summed_position_group.h"

namespace cellmetry {

namespace {

// One row whose square is a constant: the part of the summed units' cost no parameter moves.
// Ceres removes a block without parameters before it iterates and adds its cost to the costs it
// reports, so the solve's reported costs are the registry's.
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

// Ceres evaluates a block on one thread, and a static camera's world-tag units are 256 views:
// a unit reaches Ceres in pieces of at most this many members.
constexpr size_t kMaxGroupMembers = 64;

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

void CeresAdapter::View::Reset() {
  problem.reset();
  residual_ids.clear();
  unit_costs.clear();
  manifolds.clear();
  variable_blocks.clear();
  rows.clear();
}

void CeresAdapter::Reset() {
  for_evaluation_.Reset();
  for_solving_.Reset();
}

ceres::Problem& CeresAdapter::for_evaluation() {
  if (!for_evaluation_.problem) Build(/*summed=*/false, &for_evaluation_);
  return *for_evaluation_.problem;
}

ceres::Problem& CeresAdapter::for_solving() {
  if (!for_solving_.problem) Build(/*summed=*/true, &for_solving_);
  return *for_solving_.problem;
}

void CeresAdapter::Build(bool summed, View* view) {
  view->Reset();
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  options.enable_fast_removal = false;
  view->problem = std::make_unique<ceres::Problem>(options);
  AddResiduals(summed, view);
  SetParameterBlocks(view);
}

void CeresAdapter::AddResidual(ceres::CostFunction* cost, ceres::LossFunction* loss, int k,
                               View* view) {
  std::vector<double*>& pointers = view->scratch_pointers;
  pointers.clear();
  for (int b : registry_.blocks_of(k)) pointers.push_back(registry_.values(b));
  view->residual_ids.push_back(view->problem->AddResidualBlock(cost, loss, pointers));
}

void CeresAdapter::AddResiduals(bool summed, View* view) {
  const EvaluationLayout& layout = layout_;
  double constant_squared_norm = 0.0;
  for (int u = 0; u < layout.num_units(); ++u) {
    constant_squared_norm += AddUnit(u, summed, view);
    if (summed) continue;  // the rows' order matters only to Evaluate()
    for (int i = layout.unit_start[u]; i < layout.unit_start[u + 1]; ++i) {
      const int k = layout.unit_blocks[i];
      const int first_row = registry_.residual_rows()[k];
      const int rows = registry_.cost(k)->num_residuals();
      for (int row = first_row; row < first_row + rows; ++row) view->rows.push_back(row);
    }
  }
  if (constant_squared_norm > 0.0) {
    view->unit_costs.push_back(std::make_unique<ConstantCost>(constant_squared_norm));
    view->residual_ids.push_back(view->problem->AddResidualBlock(view->unit_costs.back().get(),
                                                                 nullptr, std::vector<double*>{}));
  }
  // A permutation of the rows is the identity exactly when it is sorted.
  if (std::is_sorted(view->rows.begin(), view->rows.end())) view->rows.clear();
}

double CeresAdapter::AddUnit(int u, bool summed, View* view) {
  const EvaluationLayout& layout = layout_;
  const int* first = layout.unit_blocks.data() + layout.unit_start[u];
  const int* last = layout.unit_blocks.data() + layout.unit_start[u + 1];
  // A loss acts on a Ceres block's whole norm, and each member's must see its own.
  const bool group = layout.SharesPrediction(u) &&
                     std::all_of(first, last, [&](int k) { return registry_.loss(k) == nullptr; });
  if (!group) {
    for (const int* k = first; k != last; ++k) {
      AddResidual(registry_.cost(*k), registry_.loss(*k), *k, view);
    }
    return 0.0;
  }
  std::vector<const SharedPredictionCost*> members;
  for (const int* k = first; k != last; ++k) {
    members.push_back(static_cast<const SharedPredictionCost*>(registry_.cost(*k)));
  }
  if (summed) {
    if (auto summed_unit = SummedPositionGroup::Make(members)) {
      const double constant_squared_norm = summed_unit->constant_squared_norm();
      view->unit_costs.push_back(std::move(summed_unit));
      AddResidual(view->unit_costs.back().get(), nullptr, *first, view);
      return constant_squared_norm;
    }
  }
  for (size_t begin = 0; begin < members.size(); begin += kMaxGroupMembers) {
    const size_t end = std::min(members.size(), begin + kMaxGroupMembers);
    view->unit_costs.push_back(std::make_unique<SharedPredictionGroup>(
        std::vector<const SharedPredictionCost*>(members.begin() + begin, members.begin() + end)));
    AddResidual(view->unit_costs.back().get(), nullptr, *first, view);
  }
  return 0.0;
}

void CeresAdapter::SetParameterBlocks(View* view) {
  for (int b = 0; b < registry_.num_blocks(); ++b) {
    if (!registry_.used(b)) continue;
    const std::vector<Parameter>& params = registry_.block_parameters(b);
    double* values = registry_.values(b);
    std::vector<int> fixed;
    for (size_t i = 0; i < params.size(); ++i) {
      const Parameter& p = params[i];
      if (p.fixed) {
        fixed.push_back(static_cast<int>(i));
        continue;
      }
      if (p.lower) view->problem->SetParameterLowerBound(values, static_cast<int>(i), *p.lower);
      if (p.upper) view->problem->SetParameterUpperBound(values, static_cast<int>(i), *p.upper);
    }
    if (fixed.size() == params.size()) {
      view->problem->SetParameterBlockConstant(values);
      continue;
    }
    if (!fixed.empty()) {
      view->manifolds.push_back(
          std::make_unique<ceres::SubsetManifold>(static_cast<int>(params.size()), fixed));
      view->problem->SetManifold(values, view->manifolds.back().get());
    }
    view->variable_blocks.push_back(values);
  }
}

bool CeresAdapter::Evaluate(double* cost, Eigen::VectorXd* residuals, Eigen::MatrixXd* jacobian,
                            bool apply_loss) {
  ceres::CRSMatrix crs;
  ceres::Problem& ceres = for_evaluation();
  if (!EvaluateCeres(ceres, for_evaluation_.variable_blocks, for_evaluation_.residual_ids,
                     apply_loss, cost, residuals, jacobian ? &crs : nullptr)) {
    return false;
  }
  // Ceres's rows in the registry's order (Build: units it evaluates as one block).
  const std::vector<int>& rows = for_evaluation_.rows;
  auto row_of = [&](int ceres_row) { return rows.empty() ? ceres_row : rows[ceres_row]; };
  if (residuals && !rows.empty()) {
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
