// Problem's shared predictions (problem.h, shared_prediction_cost.h): which residual blocks
// predict the same, and one prediction evaluated for them.
#include <map>
#include <utility>

#include "cellmetry/estimation/problem.h"
#include "cellmetry/estimation/shared_prediction_cost.h"
#include "problem_blocks.h"

namespace cellmetry {

void Problem::BuildPredictionUnits() {
  const int num_blocks = static_cast<int>(evaluation_order_.size());
  // Each block's unit: a new one at a block that shares nothing or at the first of its key
  // and parameter blocks (so units are in the order of their first block).
  std::vector<int> unit_of_block(num_blocks);
  std::vector<int> unit_size;
  std::map<std::pair<const void*, std::vector<int>>, int> unit_of_key;
  shares_prediction_.clear();
  for (int k = 0; k < num_blocks; ++k) {
    const auto* shared = dynamic_cast<const SharedPredictionCost*>(evaluation_order_[k].first);
    const void* key = shared ? shared->prediction_key() : nullptr;
    int unit = static_cast<int>(unit_size.size());
    if (key != nullptr) {
      unit = unit_of_key.try_emplace({key, *evaluation_order_[k].second}, unit).first->second;
    }
    if (unit == static_cast<int>(unit_size.size())) {
      unit_size.push_back(0);
      shares_prediction_.push_back(0);
    }
    ++unit_size[unit];
    unit_of_block[k] = unit;
  }
  const int num_units = static_cast<int>(unit_size.size());
  unit_start_.assign(num_units + 1, 0);
  for (int u = 0; u < num_units; ++u) {
    unit_start_[u + 1] = unit_start_[u] + unit_size[u];
    // One block alone is evaluated as any other (Evaluate is Predict and Compare).
    shares_prediction_[u] = unit_size[u] > 1;
  }
  unit_blocks_.resize(num_blocks);
  std::vector<int> next(unit_start_.begin(), unit_start_.end() - 1);
  for (int k = 0; k < num_blocks; ++k) unit_blocks_[next[unit_of_block[k]]++] = k;
}

bool Problem::PredictBlock(int k, BlockEvaluation* scratch, Pose* prediction) const {
  const auto* cost = static_cast<const SharedPredictionCost*>(evaluation_order_[k].first);
  const std::vector<int>& block_ids = *evaluation_order_[k].second;
  scratch->parameters.clear();
  scratch->jacobians.resize(block_ids.size());
  scratch->pointers.assign(block_ids.size(), nullptr);
  for (size_t slot = 0; slot < block_ids.size(); ++slot) {
    scratch->parameters.push_back(values(block_ids[slot]));
    if (!scratch->asked[slot]) continue;
    scratch->jacobians[slot].resize(3 * blocks_[block_ids[slot]]->params.size());
    scratch->pointers[slot] = scratch->jacobians[slot].data();
  }
  return cost->Predict(scratch->parameters.data(), prediction, scratch->pointers.data());
}

}  // namespace cellmetry
