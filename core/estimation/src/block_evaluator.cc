// BlockEvaluator (block_evaluator.h): one residual block's cost function called directly.
#include "block_evaluator.h"

#include <vector>

#include "cellmetry/estimation/shared_prediction_cost.h"

namespace cellmetry {

void BlockEvaluator::AskFreeSlots(int k) {
  asked_.assign(registry_.blocks_of(k).size(), 0);
  const EvaluationLayout::EntryRange range = layout_.block_entries[k];
  for (int e = range.begin; e < range.end; ++e) asked_[layout_.entries[e].slot] = 1;
}

void BlockEvaluator::AskSlotsOf(int k, const std::vector<bool>& asked_blocks) {
  const std::vector<int>& block_ids = registry_.blocks_of(k);
  asked_.resize(block_ids.size());
  for (size_t slot = 0; slot < block_ids.size(); ++slot) {
    asked_[slot] = asked_blocks[block_ids[slot]];
  }
}

void BlockEvaluator::PrepareSlots(int k, int num_rows, bool with_jacobians) {
  const std::vector<int>& block_ids = registry_.blocks_of(k);
  parameters_.clear();
  jacobians_.resize(block_ids.size());
  pointers_.assign(block_ids.size(), nullptr);
  asked_.resize(block_ids.size(), 0);
  for (size_t slot = 0; slot < block_ids.size(); ++slot) {
    parameters_.push_back(registry_.values(block_ids[slot]));
    if (!with_jacobians || !asked_[slot]) continue;  // not differentiated
    jacobians_[slot].resize(static_cast<size_t>(num_rows) * registry_.block_size(block_ids[slot]));
    pointers_[slot] = jacobians_[slot].data();
  }
}

bool BlockEvaluator::Evaluate(int k, bool with_jacobians) {
  const ceres::CostFunction* cost = registry_.cost(k);
  const int num_rows = cost->num_residuals();
  PrepareSlots(k, num_rows, with_jacobians);
  residuals_.resize(num_rows);
  return cost->Evaluate(parameters_.data(), residuals_.data(),
                        with_jacobians ? pointers_.data() : nullptr);
}

bool BlockEvaluator::Predict(int k, Pose* prediction) {
  const auto* cost = static_cast<const SharedPredictionCost*>(registry_.cost(k));
  PrepareSlots(k, 3, /*with_jacobians=*/true);  // the tangent's 3 rows, where asked
  return cost->Predict(parameters_.data(), prediction, pointers_.data());
}

int BlockEvaluator::GatherFreeColumns(int k, int num_rows, std::vector<double>* rows) const {
  const std::vector<int>& block_ids = registry_.blocks_of(k);
  const int first = layout_.block_entries[k].begin;
  const int width = layout_.block_entries[k].size();
  rows->resize(static_cast<size_t>(num_rows) * width);
  for (int j = 0; j < width; ++j) {
    const EvaluationLayout::Entry& e = layout_.entries[first + j];
    const int block_width = registry_.block_size(block_ids[e.slot]);
    for (int row = 0; row < num_rows; ++row) {
      (*rows)[row * width + j] = At(e.slot, row, block_width, e.index);
    }
  }
  return width;
}

}  // namespace cellmetry
