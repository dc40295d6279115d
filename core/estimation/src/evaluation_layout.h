// EvaluationLayout: what the evaluators walk, made by BlockRegistry::Build() from its rows and
// columns (internal to the estimation layer). Plain data, read on every core at once: it changes
// only inside Build().
//
//   entries       per residual block, the free columns its rows hold, in column order, each with
//                 the slot (which of the block's parameter blocks) and the entry it comes from.
//                 Blocks over the same parameter blocks (every observation of one tool by one
//                 camera) hold the same entries, stored once.
//   column groups residual blocks whose free columns are the same list share a group: the normal
//                 equations sum each group densely (normal_equations_evaluator.h).
//   row_start     the sparse Jacobian's compressed row pointers (per row, then the end).
//   units         the residual blocks that share one prediction (shared_prediction_cost.h: the
//                 same key over the same parameter blocks), each unit's blocks ascending, units
//                 in the order of their first block, at most kMaxUnitBlocks each; a block that
//                 shares nothing is a unit alone. A unit of more than one block is evaluated
//                 once for all of them.
//   chunks        consecutive units in runs of about the same number of blocks: how the
//                 evaluations split among the cores. A range of units would put a static
//                 camera's world-tag units, thousands of blocks, all at the end in one range.
#pragma once

#include <vector>

#include "cellmetry/estimation/block_registry.h"

namespace cellmetry {

struct EvaluationLayout {
  struct Entry {
    int column, slot, index;
  };
  struct EntryRange {
    int begin = 0, end = 0;
    int size() const { return end - begin; }
  };

  std::vector<Entry> entries;
  std::vector<EntryRange> block_entries;        // per residual block, into `entries`
  std::vector<int> column_group;                // per residual block
  std::vector<std::vector<int>> group_columns;  // per group, ascending
  std::vector<int> row_start;
  std::vector<int> unit_blocks;
  std::vector<int> unit_start;   // per unit, into unit_blocks; then the end
  std::vector<int> chunk_start;  // per chunk, its first unit; then the end

  int num_units() const { return static_cast<int>(unit_start.size()) - 1; }
  int first_block(int u) const { return unit_blocks[unit_start[u]]; }
  bool SharesPrediction(int u) const { return unit_start[u + 1] - unit_start[u] > 1; }
  int num_chunks() const { return static_cast<int>(chunk_start.size()) - 1; }

  // Made again from `registry`'s rows and columns, unless neither the residual blocks (which
  // are only ever appended) nor the free columns changed since the last time: a new robust
  // loss, or an entry held and freed again, keeps the layout.
  void Update(const BlockRegistry& registry);

 private:
  void LayOutEntries(const BlockRegistry& registry);
  void LayOutUnits(const BlockRegistry& registry);
  void LayOutChunks(const std::vector<int>& unit_size, int num_blocks);

  // What the layout was made from.
  int made_for_blocks_ = -1;
  std::vector<std::vector<int>> made_for_free_columns_;
};

}  // namespace cellmetry
