// EvaluationLayout (evaluation_layout.h): the free columns of each residual block, the units of
// blocks that share a prediction, and the chunks the cores take.
#include "evaluation_layout.h"

#include <algorithm>
#include <unordered_map>
#include <vector>

#include "cellmetry/estimation/shared_prediction_cost.h"
#include "column_patterns.h"

namespace cellmetry {

namespace {

// A unit's blocks are summed by one thread: a static camera's world-tag observations (5,000 on
// bench_scale's factory cell, all of them after the robots' blocks) in one unit were one
// thread's serial tail. Beyond this many blocks the prediction is evaluated again for the next
// ones, once per 256 comparisons.
constexpr int kMaxUnitBlocks = 256;

// Each list of parameter blocks a residual block reads, with the entries its rows hold and
// their column group, worked out once per list (lists are interned: one address per list).
class EntryPatterns {
 public:
  struct Pattern {
    EvaluationLayout::EntryRange entries;
    int group = 0;
  };

  EntryPatterns(const std::vector<std::vector<int>>& free_columns,
                std::vector<EvaluationLayout::Entry>* entries)
      : free_columns_(free_columns), entries_(entries) {}

  const Pattern& Of(const std::vector<int>& block_ids) {
    auto [it, inserted] = of_list_.try_emplace(&block_ids);
    if (inserted) it->second = Make(block_ids);
    return it->second;
  }

  const std::vector<std::vector<int>>& groups() const { return groups_.groups(); }

 private:
  // The free entries of `block_ids`, in column order, appended to entries_.
  Pattern Make(const std::vector<int>& block_ids) {
    Pattern pattern;
    pattern.entries.begin = static_cast<int>(entries_->size());
    for (size_t slot = 0; slot < block_ids.size(); ++slot) {
      const std::vector<int>& column_of = free_columns_[block_ids[slot]];
      for (size_t i = 0; i < column_of.size(); ++i) {
        if (column_of[i] >= 0) {
          entries_->push_back({column_of[i], static_cast<int>(slot), static_cast<int>(i)});
        }
      }
    }
    pattern.entries.end = static_cast<int>(entries_->size());
    const auto first = entries_->begin() + pattern.entries.begin;
    std::sort(first, entries_->end(),
              [](const EvaluationLayout::Entry& a, const EvaluationLayout::Entry& b) {
                return a.column < b.column;
              });
    columns_.clear();
    for (auto e = first; e != entries_->end(); ++e) columns_.push_back(e->column);
    pattern.group = groups_.GroupOf(columns_.data(), static_cast<int>(columns_.size()));
    return pattern;
  }

  const std::vector<std::vector<int>>& free_columns_;
  std::vector<EvaluationLayout::Entry>* entries_;
  std::unordered_map<const std::vector<int>*, Pattern> of_list_;
  ColumnPatterns groups_;
  std::vector<int> columns_;  // Make's, kept to spare an allocation
};

}  // namespace

void EvaluationLayout::Update(const BlockRegistry& registry) {
  if (made_for_blocks_ == registry.num_residual_blocks() &&
      made_for_free_columns_ == registry.free_columns()) {
    return;
  }
  made_for_blocks_ = registry.num_residual_blocks();
  made_for_free_columns_ = registry.free_columns();
  LayOutEntries(registry);
  LayOutUnits(registry);
}

void EvaluationLayout::LayOutEntries(const BlockRegistry& registry) {
  const int num_blocks = registry.num_residual_blocks();
  const int num_residuals = registry.num_residuals();
  const std::vector<int>& first_row = registry.residual_rows();
  entries.clear();
  EntryPatterns patterns(registry.free_columns(), &entries);
  block_entries.resize(num_blocks);
  row_start.assign(num_residuals + 1, 0);
  column_group.assign(num_blocks, 0);
  for (int k = 0; k < num_blocks; ++k) {
    const std::vector<int>& block_ids = registry.blocks_of(k);
    // Blocks come in runs over the same parameter blocks: the previous one's, without a lookup.
    if (k > 0 && &block_ids == &registry.blocks_of(k - 1)) {
      block_entries[k] = block_entries[k - 1];
      column_group[k] = column_group[k - 1];
    } else {
      const EntryPatterns::Pattern& pattern = patterns.Of(block_ids);
      block_entries[k] = pattern.entries;
      column_group[k] = pattern.group;
    }
    const int width = block_entries[k].size();
    const int num_rows = registry.cost(k)->num_residuals();
    for (int row = 0; row < num_rows; ++row) row_start[first_row[k] + row + 1] = width;
  }
  for (int row = 0; row < num_residuals; ++row) row_start[row + 1] += row_start[row];
  group_columns = patterns.groups();
}

void EvaluationLayout::LayOutUnits(const BlockRegistry& registry) {
  const int num_blocks = registry.num_residual_blocks();
  // Each block's unit: a new one at a block that shares nothing or at the first of its key
  // and parameter blocks (so units are in the order of their first block).
  std::vector<int> unit_of_block(num_blocks);
  std::vector<int> unit_size;
  // Per key, its latest unit and that unit's parameter blocks: a block with the key over other
  // blocks starts a unit of its own (shared by the blocks after it that match it).
  std::unordered_map<const void*, int> unit_of_key;
  std::vector<const std::vector<int>*> blocks_of_unit;
  for (int k = 0; k < num_blocks; ++k) {
    const auto* shared = dynamic_cast<const SharedPredictionCost*>(registry.cost(k));
    const void* key = shared ? shared->prediction_key() : nullptr;
    const std::vector<int>* block_ids = &registry.blocks_of(k);
    int unit = static_cast<int>(unit_size.size());
    if (key != nullptr) {
      auto [it, inserted] = unit_of_key.try_emplace(key, unit);
      if (!inserted && blocks_of_unit[it->second] == block_ids &&  // interned lists
          unit_size[it->second] < kMaxUnitBlocks) {
        unit = it->second;
      }
      it->second = unit;
    }
    if (unit == static_cast<int>(unit_size.size())) {
      unit_size.push_back(0);
      blocks_of_unit.push_back(block_ids);
    }
    ++unit_size[unit];
    unit_of_block[k] = unit;
  }
  const int units = static_cast<int>(unit_size.size());
  unit_start.assign(units + 1, 0);
  for (int u = 0; u < units; ++u) unit_start[u + 1] = unit_start[u] + unit_size[u];
  unit_blocks.resize(num_blocks);
  std::vector<int> next(unit_start.begin(), unit_start.end() - 1);
  for (int k = 0; k < num_blocks; ++k) unit_blocks[next[unit_of_block[k]]++] = k;
  LayOutChunks(unit_size, num_blocks);
}

void EvaluationLayout::LayOutChunks(const std::vector<int>& unit_size, int num_blocks) {
  // Chunks of at least 256 blocks and at most about 64 of them (the normal equations hold an
  // n x n sum per chunk: 1.7 MB at the 456 columns of bench_scale's largest cell).
  const int chunk_blocks = std::max(256, num_blocks / 64);
  const int units = static_cast<int>(unit_size.size());
  chunk_start.assign(1, 0);
  for (int u = 0, in_chunk = 0; u < units; ++u) {
    in_chunk += unit_size[u];
    if (in_chunk >= chunk_blocks || u + 1 == units) {
      chunk_start.push_back(u + 1);
      in_chunk = 0;
    }
  }
}

}  // namespace cellmetry
