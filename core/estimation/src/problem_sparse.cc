// Problem's sparse evaluation (problem.h): the layout Build() fixes (per residual block, the free
// columns its rows hold), then the residuals with the sparse Jacobian or its Gram rows
// (EvaluateSparse), a chosen set of columns (EvaluateSparseColumns) and Linearize, block by
// block on every core. Blocks that share a prediction are evaluated once per unit
// (prediction_units.cc); the dense, Ceres-evaluated Evaluate() is in problem_ceres.cc.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <unordered_map>
#include <utility>
#include <vector>

#include "cellmetry/estimation/problem.h"
#include "column_patterns.h"
#include "problem_blocks.h"

namespace cellmetry {

void Problem::BuildSparseLayout() {
  // The layout is a function of the residual blocks (appended only) and the free columns: a
  // Build that changed neither (a new robust loss, a parameter held and freed again) keeps it.
  const int num_blocks = static_cast<int>(evaluation_order_.size());
  if (layout_num_blocks_ == num_blocks && layout_free_column_ == free_column_) return;
  layout_num_blocks_ = num_blocks;
  layout_free_column_ = free_column_;
  // Each residual block's rows hold the same columns: the free entries of its blocks, in
  // column order. Blocks over the same parameter blocks (every observation of one tool by one
  // camera) have the same entries: worked out and stored once per list of blocks.
  struct Pattern {
    EntryRange entries;  // in sparse_entries_
    int group = 0;
  };
  std::unordered_map<const std::vector<int>*, Pattern> patterns_of_blocks;  // interned lists
  ColumnPatterns patterns;
  std::vector<int> columns;
  sparse_entries_.clear();
  auto pattern_of = [&](const std::vector<int>& block_ids) -> const Pattern& {
    auto [it, inserted] = patterns_of_blocks.try_emplace(&block_ids);
    Pattern& pattern = it->second;
    if (!inserted) return pattern;
    pattern.entries.begin = static_cast<int>(sparse_entries_.size());
    for (size_t slot = 0; slot < block_ids.size(); ++slot) {
      const auto& free_column = free_column_[block_ids[slot]];
      for (size_t i = 0; i < free_column.size(); ++i) {
        if (free_column[i] >= 0) {
          sparse_entries_.push_back(
              {free_column[i], static_cast<int>(slot), static_cast<int>(i)});
        }
      }
    }
    pattern.entries.end = static_cast<int>(sparse_entries_.size());
    const auto first = sparse_entries_.begin() + pattern.entries.begin;
    std::sort(first, sparse_entries_.end(),
              [](const SparseEntry& a, const SparseEntry& b) { return a.column < b.column; });
    // Column groups: the same column list, the same group.
    columns.clear();
    for (auto e = first; e != sparse_entries_.end(); ++e) columns.push_back(e->column);
    pattern.group = patterns.GroupOf(columns.data(), static_cast<int>(columns.size()));
    return pattern;
  };
  block_entries_.resize(num_blocks);
  sparse_row_start_.assign(num_residuals_ + 1, 0);
  column_group_.assign(num_blocks, 0);
  for (int k = 0; k < num_blocks; ++k) {
    const std::vector<int>& block_ids = *evaluation_order_[k].second;
    // Blocks come in runs over the same parameter blocks: the previous one's, without a lookup.
    const bool as_previous = k > 0 && &block_ids == evaluation_order_[k - 1].second;
    if (as_previous) {
      block_entries_[k] = block_entries_[k - 1];
      column_group_[k] = column_group_[k - 1];
    } else {
      const Pattern& pattern = pattern_of(block_ids);
      block_entries_[k] = pattern.entries;
      column_group_[k] = pattern.group;
    }
    const int width = block_entries_[k].end - block_entries_[k].begin;
    const int num_rows = evaluation_order_[k].first->num_residuals();
    for (int row = 0; row < num_rows; ++row) sparse_row_start_[rows_[k] + row + 1] = width;
  }
  for (int row = 0; row < num_residuals_; ++row) {
    sparse_row_start_[row + 1] += sparse_row_start_[row];
  }
  group_columns_ = patterns.groups();
  BuildPredictionUnits();
}

void Problem::PrepareSlots(int k, int num_rows, bool with_jacobians,
                           BlockEvaluation* scratch) const {
  const std::vector<int>& block_ids = *evaluation_order_[k].second;
  scratch->parameters.clear();
  scratch->jacobians.resize(block_ids.size());
  scratch->pointers.assign(block_ids.size(), nullptr);
  scratch->asked.resize(block_ids.size(), 0);
  for (size_t slot = 0; slot < block_ids.size(); ++slot) {
    scratch->parameters.push_back(values(block_ids[slot]));
    if (!with_jacobians || !scratch->asked[slot]) continue;  // not differentiated
    scratch->jacobians[slot].resize(static_cast<size_t>(num_rows) *
                                    blocks_[block_ids[slot]]->params.size());
    scratch->pointers[slot] = scratch->jacobians[slot].data();
  }
}

bool Problem::EvaluateBlock(int k, bool with_jacobians, BlockEvaluation* scratch) const {
  ceres::CostFunction* cost = evaluation_order_[k].first;
  const int num_rows = cost->num_residuals();
  PrepareSlots(k, num_rows, with_jacobians, scratch);
  scratch->residuals.resize(num_rows);
  return cost->Evaluate(scratch->parameters.data(), scratch->residuals.data(),
                        with_jacobians ? scratch->pointers.data() : nullptr);
}

int Problem::GatherFreeColumns(int k, int num_rows, const BlockEvaluation& scratch,
                               std::vector<double>* rows) const {
  const std::vector<int>& block_ids = *evaluation_order_[k].second;
  const int first = block_entries_[k].begin;
  const int width = block_entries_[k].end - first;
  rows->resize(static_cast<size_t>(num_rows) * width);
  for (int j = 0; j < width; ++j) {
    const SparseEntry& e = sparse_entries_[first + j];
    const int block_width = static_cast<int>(blocks_[block_ids[e.slot]]->params.size());
    for (int row = 0; row < num_rows; ++row) {
      (*rows)[row * width + j] = scratch.At(e.slot, row, block_width, e.index);
    }
  }
  return width;
}

void Problem::AskFreeSlots(int k, BlockEvaluation* scratch) const {
  scratch->asked.assign(evaluation_order_[k].second->size(), 0);
  for (int e = block_entries_[k].begin; e < block_entries_[k].end; ++e) {
    scratch->asked[sparse_entries_[e].slot] = 1;
  }
}

bool Problem::EvaluateBlockRows(int u, BlockEvaluation* scratch, const SparseOutput& out) const {
  const int k = unit_blocks_[unit_start_[u]];
  const bool with_jacobian = out.column_index != nullptr || out.gram != nullptr;
  AskFreeSlots(k, scratch);
  if (!EvaluateBlock(k, with_jacobian, scratch)) return false;
  std::copy(scratch->residuals.begin(), scratch->residuals.end(), out.r + rows_[k]);
  const int num_rows = static_cast<int>(scratch->residuals.size());
  if (out.column_index) {
    WriteBlockRows(k, *scratch, &sparse_row_start_[rows_[k]], out.column_index, out.entries);
  }
  if (out.gram) {  // a block alone stands for itself
    const int first = out.gram_unit_row[u];
    WriteBlockRows(k, *scratch, out.gram->rows.outerIndexPtr() + first,
                   out.gram->rows.innerIndexPtr(), out.gram->rows.valuePtr());
    for (int row = 0; row < num_rows; ++row) out.gram->block[static_cast<size_t>(first + row)] = k;
  }
  return true;
}

void Problem::WriteBlockRows(int k, const BlockEvaluation& scratch, const int* row_start,
                             int* column_index, double* entries) const {
  const std::vector<int>& block_ids = *evaluation_order_[k].second;
  const int num_rows = static_cast<int>(scratch.residuals.size());
  for (int row = 0; row < num_rows; ++row) {
    int at = row_start[row];
    for (int k_e = block_entries_[k].begin; k_e < block_entries_[k].end; ++k_e) {
      const SparseEntry& e = sparse_entries_[k_e];
      const int width = static_cast<int>(blocks_[block_ids[e.slot]]->params.size());
      column_index[at] = e.column;
      entries[at++] = scratch.At(e.slot, row, width, e.index);
    }
  }
}

int Problem::NumGramRows(std::vector<int>* unit_row) const {
  const int num_units = static_cast<int>(unit_start_.size()) - 1;
  if (unit_row) unit_row->assign(static_cast<size_t>(num_units) + 1, 0);
  int total = 0;
  for (int u = 0; u < num_units; ++u) {
    const int k = unit_blocks_[unit_start_[u]];
    const int end = k + 1 < static_cast<int>(rows_.size()) ? rows_[k + 1] : num_residuals_;
    total += SharesPrediction(u) ? 3 : end - rows_[k];
    if (unit_row) (*unit_row)[static_cast<size_t>(u) + 1] = total;
  }
  return total;
}

// Where few captures share a prediction the rows are mostly J's own: J itself serves (GramOf).
// bench_scale's factory cell (one capture per pose, its world tags shared) would have half of
// J's rows, and its BM_Linearize took 29 ms instead of 16.
bool Problem::HasGramRows() const { return 4 * NumGramRows(nullptr) <= num_residuals_; }

std::vector<int> Problem::LayOutGramRows(GramRows* gram) const {
  *gram = GramRows{};
  if (!HasGramRows()) return {};
  const int num_units = static_cast<int>(unit_start_.size()) - 1;
  std::vector<int> unit_row;
  const int num_rows = NumGramRows(&unit_row);
  int entries = 0;
  for (int u = 0; u < num_units; ++u) {
    const int k = unit_blocks_[unit_start_[u]];
    entries += (unit_row[u + 1] - unit_row[u]) * (block_entries_[k].end - block_entries_[k].begin);
  }
  gram->rows.resize(num_rows, num_free());
  gram->rows.resizeNonZeros(entries);
  gram->block.assign(static_cast<size_t>(num_rows), -1);
  gram->row_of_block.assign(evaluation_order_.size(), -1);
  int* starts = gram->rows.outerIndexPtr();
  starts[0] = 0;
  for (int u = 0; u < num_units; ++u) {
    const int k = unit_blocks_[unit_start_[u]];
    const int width = block_entries_[k].end - block_entries_[k].begin;
    for (int row = unit_row[u]; row < unit_row[u + 1]; ++row) starts[row + 1] = starts[row] + width;
    for (int i = unit_start_[u]; i < unit_start_[u + 1]; ++i) {
      gram->row_of_block[static_cast<size_t>(unit_blocks_[i])] = unit_row[u];
    }
  }
  return unit_row;
}

bool Problem::EvaluateSparse(Eigen::VectorXd* residuals, SparseJacobian* jacobian,
                             GramRows* gram) const {
  const std::vector<int>& row_start = sparse_row_start_;
  // Written in place into the compressed row storage (no triplets, no copy of a map).
  int* column_index = nullptr;
  double* entries = nullptr;
  if (jacobian) {
    jacobian->resize(num_residuals_, num_free());
    jacobian->resizeNonZeros(row_start.back());
    std::copy(row_start.begin(), row_start.end(), jacobian->outerIndexPtr());
    column_index = jacobian->innerIndexPtr();
    entries = jacobian->valuePtr();
  }
  std::vector<int> gram_unit_row;
  if (gram) gram_unit_row = LayOutGramRows(gram);
  if (gram && !jacobian && gram_unit_row.empty()) {
    throw std::logic_error("EvaluateSparse: Gram rows alone asked of a problem without them");
  }
  Eigen::VectorXd r(num_residuals_);
  const SparseOutput out{r.data(), column_index, entries,
                         gram_unit_row.empty() ? nullptr : gram, gram_unit_row.data()};
  const int num_chunks = static_cast<int>(chunk_start_.size()) - 1;
  std::atomic<bool> valid{true};
  tbb::parallel_for(tbb::blocked_range<int>(0, num_chunks, 1), [&](const auto& chunks) {
    BlockEvaluation scratch;
    for (int u = chunk_start_[chunks.begin()]; u != chunk_start_[chunks.end()] && valid; ++u) {
      const bool ok = SharesPrediction(u) ? EvaluateSharedRows(u, &scratch, out)
                                          : EvaluateBlockRows(u, &scratch, out);
      if (!ok) valid = false;
    }
  });
  if (!valid) {
    if (jacobian) jacobian->setZero();
    return false;
  }
  if (residuals) *residuals = std::move(r);
  return true;
}

namespace {

// Where a residual block's Jacobian entries go: (column, parameter block of the residual, entry
// in it), in column order.
struct ColumnEntry {
  int column, slot, index;
  bool operator<(const ColumnEntry& other) const { return column < other.column; }
};

// Per residual block, the entries of the asked-for blocks' free columns (`renumbered`: free
// column -> output column, -1 when not asked for); `row_start`: each row's first entry.
struct ColumnLayout {
  std::vector<std::vector<ColumnEntry>> entries_of;
  std::vector<int> row_start;
};

ColumnLayout LayOutColumns(
    const std::vector<std::pair<ceres::CostFunction*, const std::vector<int>*>>& evaluation_order,
    const std::vector<std::vector<int>>& free_column, const std::vector<int>& first_row,
    int num_residuals, const std::vector<bool>& asked, const std::vector<int>& renumbered) {
  ColumnLayout out;
  out.entries_of.resize(evaluation_order.size());
  out.row_start.assign(num_residuals + 1, 0);
  for (size_t k = 0; k < evaluation_order.size(); ++k) {
    const auto& [cost, ids] = evaluation_order[k];
    const std::vector<int>& block_ids = *ids;
    for (size_t slot = 0; slot < block_ids.size(); ++slot) {
      if (!asked[block_ids[slot]]) continue;
      const auto& columns = free_column[block_ids[slot]];
      for (size_t i = 0; i < columns.size(); ++i) {
        if (columns[i] < 0) continue;
        out.entries_of[k].push_back(
            {renumbered[columns[i]], static_cast<int>(slot), static_cast<int>(i)});
      }
    }
    std::sort(out.entries_of[k].begin(), out.entries_of[k].end());
    for (int row = 0; row < cost->num_residuals(); ++row) {
      out.row_start[first_row[k] + row + 1] = static_cast<int>(out.entries_of[k].size());
    }
  }
  for (int row = 0; row < num_residuals; ++row) out.row_start[row + 1] += out.row_start[row];
  return out;
}

}  // namespace

bool Problem::EvaluateSparseColumns(const std::vector<int>& blocks, SparseJacobian* jacobian,
                                    std::vector<int>* columns) const {
  std::vector<bool> asked(blocks_.size(), false);
  for (int b : blocks) asked.at(b) = true;
  std::vector<int> renumbered(free_.size(), -1);
  columns->clear();
  for (size_t c = 0; c < free_.size(); ++c) {
    if (!asked[free_[c].block]) continue;
    renumbered[c] = static_cast<int>(columns->size());
    columns->push_back(static_cast<int>(c));
  }
  const ColumnLayout layout =
      LayOutColumns(evaluation_order_, free_column_, rows_, num_residuals_, asked, renumbered);
  std::vector<int> column_index(static_cast<size_t>(layout.row_start.back()));
  std::vector<double> entries(column_index.size());
  std::atomic<bool> valid{true};
  const int num_blocks = static_cast<int>(evaluation_order_.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, num_blocks, 64), [&](const auto& range) {
    BlockEvaluation scratch;
    for (int k = range.begin(); k != range.end() && valid; ++k) {
      if (layout.entries_of[k].empty()) continue;  // reads none of the blocks asked for
      const std::vector<int>& block_ids = *evaluation_order_[k].second;
      scratch.asked.resize(block_ids.size());
      for (size_t slot = 0; slot < block_ids.size(); ++slot) {
        scratch.asked[slot] = asked[block_ids[slot]];
      }
      if (!EvaluateBlock(k, true, &scratch)) {
        valid = false;
        break;
      }
      const int num_rows = static_cast<int>(scratch.residuals.size());
      for (int row = 0; row < num_rows; ++row) {
        int at = layout.row_start[rows_[k] + row];
        for (const ColumnEntry& e : layout.entries_of[k]) {
          const int width = static_cast<int>(blocks_[block_ids[e.slot]]->params.size());
          column_index[at] = e.column;
          entries[at++] = scratch.At(e.slot, row, width, e.index);
        }
      }
    }
  });
  if (!valid) return false;
  *jacobian = Eigen::Map<const SparseJacobian>(
      num_residuals_, static_cast<Eigen::Index>(columns->size()),
      static_cast<Eigen::Index>(entries.size()), layout.row_start.data(), column_index.data(),
      entries.data());
  return true;
}

Linearization Linearize(Problem& problem) {
  Linearization at;
  at.valid = problem.EvaluateSparse(&at.residuals, &at.jacobian, &at.gram);
  return at;
}

const SparseJacobian& GramOf(const Linearization& at) {
  return at.gram.rows.rows() > 0 || at.jacobian.rows() == 0 ? at.gram.rows : at.jacobian;
}

}  // namespace cellmetry
