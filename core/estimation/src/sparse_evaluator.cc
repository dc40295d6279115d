// SparseEvaluator (sparse_evaluator.h): residuals, the sparse Jacobian and its Gram rows, and a
// chosen set of columns, block by block on every core.
#include "sparse_evaluator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <utility>
#include <vector>

#include "cellmetry/estimation/shared_prediction_cost.h"
#include "block_evaluator.h"

namespace cellmetry {

bool SparseEvaluator::Evaluate(Eigen::VectorXd* residuals, SparseJacobian* jacobian,
                               GramRows* gram) const {
  const int num_residuals = registry_.num_residuals();
  const std::vector<int>& row_start = layout_.row_start;
  int* column_index = nullptr;
  double* entries = nullptr;
  if (jacobian) {
    jacobian->resize(num_residuals, registry_.num_free());
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
  Eigen::VectorXd r(num_residuals);
  const Output out{r.data(), column_index, entries, gram_unit_row.empty() ? nullptr : gram,
                   gram_unit_row.data()};
  std::atomic<bool> valid{true};
  tbb::parallel_for(tbb::blocked_range<int>(0, layout_.num_chunks(), 1), [&](const auto& chunks) {
    BlockEvaluator block(registry_, layout_);
    std::vector<double> tangent;
    const int end = layout_.chunk_start[chunks.end()];
    for (int u = layout_.chunk_start[chunks.begin()]; u != end && valid; ++u) {
      const bool ok = layout_.SharesPrediction(u) ? EvaluateSharedRows(u, &block, &tangent, out)
                                                  : EvaluateBlockRows(u, &block, out);
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

bool SparseEvaluator::EvaluateBlockRows(int u, BlockEvaluator* block, const Output& out) const {
  const int k = layout_.first_block(u);
  const bool with_jacobian = out.column_index != nullptr || out.gram != nullptr;
  block->AskFreeSlots(k);
  if (!block->Evaluate(k, with_jacobian)) return false;
  const std::vector<double>& r = block->residuals();
  const int first_row = registry_.residual_rows()[k];
  std::copy(r.begin(), r.end(), out.r + first_row);
  if (out.column_index) {
    WriteBlockRows(k, *block, &layout_.row_start[first_row], out.column_index, out.entries);
  }
  if (out.gram) {  // a block alone stands for itself
    const int first = out.gram_unit_row[u];
    WriteBlockRows(k, *block, out.gram->rows.outerIndexPtr() + first,
                   out.gram->rows.innerIndexPtr(), out.gram->rows.valuePtr());
    const int num_rows = static_cast<int>(r.size());
    for (int row = 0; row < num_rows; ++row) out.gram->block[static_cast<size_t>(first + row)] = k;
  }
  return true;
}

void SparseEvaluator::WriteBlockRows(int k, const BlockEvaluator& block, const int* row_start,
                                     int* column_index, double* entries) const {
  const std::vector<int>& block_ids = registry_.blocks_of(k);
  const EvaluationLayout::EntryRange range = layout_.block_entries[k];
  const int num_rows = static_cast<int>(block.residuals().size());
  for (int row = 0; row < num_rows; ++row) {
    int at = row_start[row];
    for (int i = range.begin; i < range.end; ++i) {
      const EvaluationLayout::Entry& e = layout_.entries[i];
      const int width = registry_.block_size(block_ids[e.slot]);
      column_index[at] = e.column;
      entries[at++] = block.At(e.slot, row, width, e.index);
    }
  }
}

bool SparseEvaluator::EvaluateSharedRows(int u, BlockEvaluator* block, std::vector<double>* tangent,
                                         const Output& out) const {
  const bool with_jacobian = out.column_index != nullptr || out.gram != nullptr;
  const int first = layout_.first_block(u);
  if (with_jacobian) {
    block->AskFreeSlots(first);
  } else {
    block->AskNone(first);
  }
  Pose prediction;
  if (!block->Predict(first, &prediction)) return false;
  // A at the unit's free columns (every block of the unit has the same), row-major 3 x width.
  const int entry = layout_.block_entries[first].begin;
  const int width = with_jacobian ? block->GatherFreeColumns(first, 3, tangent) : 0;
  const double* a = tangent->data();
  Eigen::Matrix3d D;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();  // sum of D^T D, for the Gram rows
  for (int i = layout_.unit_start[u]; i < layout_.unit_start[u + 1]; ++i) {
    const int k = layout_.unit_blocks[i];
    const int first_row = registry_.residual_rows()[k];
    static_cast<const SharedPredictionCost*>(registry_.cost(k))
        ->Compare(prediction, out.r + first_row, with_jacobian ? &D : nullptr);
    if (!with_jacobian) continue;
    if (out.gram) information.noalias() += D.transpose() * D;
    if (out.column_index == nullptr) continue;  // the Gram rows alone
    for (int row = 0; row < 3; ++row) {         // row `row` of D A
      int at = layout_.row_start[first_row + row];
      for (int j = 0; j < width; ++j) {
        out.column_index[at] = layout_.entries[entry + j].column;
        out.entries[at++] =
            D(row, 0) * a[j] + D(row, 1) * a[width + j] + D(row, 2) * a[2 * width + j];
      }
    }
  }
  if (out.gram) AddGramRows(u, information, a, width, out);
  return true;
}

void SparseEvaluator::AddGramRows(int u, const Eigen::Matrix3d& information, const double* tangent,
                                  int width, const Output& out) const {
  // L^T with L L^T = information; its symmetric square root where rounding left it not
  // positive definite (a unit's rows then span fewer than three directions).
  Eigen::Matrix3d L_t;
  const Eigen::LLT<Eigen::Matrix3d> llt(information);
  if (llt.info() == Eigen::Success) {
    L_t = llt.matrixU();
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(information);
    L_t = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() *
          eigen.eigenvectors().transpose();
  }
  const int first = layout_.first_block(u);
  const int entry = layout_.block_entries[first].begin;
  for (int row = 0; row < 3; ++row) {
    const int gram_row = out.gram_unit_row[u] + row;
    int at = out.gram->rows.outerIndexPtr()[gram_row];
    for (int j = 0; j < width; ++j) {
      out.gram->rows.innerIndexPtr()[at] = layout_.entries[entry + j].column;
      out.gram->rows.valuePtr()[at++] = L_t(row, 0) * tangent[j] +
                                        L_t(row, 1) * tangent[width + j] +
                                        L_t(row, 2) * tangent[2 * width + j];
    }
    out.gram->block[static_cast<size_t>(gram_row)] = first;
  }
}

int SparseEvaluator::NumGramRows(std::vector<int>* unit_row) const {
  const int num_units = layout_.num_units();
  const std::vector<int>& rows = registry_.residual_rows();
  if (unit_row) unit_row->assign(static_cast<size_t>(num_units) + 1, 0);
  int total = 0;
  for (int u = 0; u < num_units; ++u) {
    const int k = layout_.first_block(u);
    const int end = k + 1 < static_cast<int>(rows.size()) ? rows[k + 1] : registry_.num_residuals();
    total += layout_.SharesPrediction(u) ? 3 : end - rows[k];
    if (unit_row) (*unit_row)[static_cast<size_t>(u) + 1] = total;
  }
  return total;
}

// Where few captures share a prediction the rows are mostly J's own: J itself serves (GramOf).
// bench_scale's factory cell (one capture per pose, its world tags shared) would have half of
// J's rows, and Gram rows made its BM_Linearize slower, not faster.
bool SparseEvaluator::HasGramRows() const {
  return 4 * NumGramRows(nullptr) <= registry_.num_residuals();
}

std::vector<int> SparseEvaluator::LayOutGramRows(GramRows* gram) const {
  *gram = GramRows{};
  if (!HasGramRows()) return {};
  const int num_units = layout_.num_units();
  std::vector<int> unit_row;
  const int num_rows = NumGramRows(&unit_row);
  int entries = 0;
  for (int u = 0; u < num_units; ++u) {
    const int width = layout_.block_entries[layout_.first_block(u)].size();
    entries += (unit_row[u + 1] - unit_row[u]) * width;
  }
  gram->rows.resize(num_rows, registry_.num_free());
  gram->rows.resizeNonZeros(entries);
  gram->block.assign(static_cast<size_t>(num_rows), -1);
  gram->row_of_block.assign(static_cast<size_t>(registry_.num_residual_blocks()), -1);
  int* starts = gram->rows.outerIndexPtr();
  starts[0] = 0;
  for (int u = 0; u < num_units; ++u) {
    const int width = layout_.block_entries[layout_.first_block(u)].size();
    for (int row = unit_row[u]; row < unit_row[u + 1]; ++row) starts[row + 1] = starts[row] + width;
    for (int i = layout_.unit_start[u]; i < layout_.unit_start[u + 1]; ++i) {
      gram->row_of_block[static_cast<size_t>(layout_.unit_blocks[i])] = unit_row[u];
    }
  }
  return unit_row;
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

ColumnLayout LayOutColumns(const BlockRegistry& registry, const std::vector<bool>& asked,
                           const std::vector<int>& renumbered) {
  const int num_blocks = registry.num_residual_blocks();
  const std::vector<int>& first_row = registry.residual_rows();
  const int num_residuals = registry.num_residuals();
  ColumnLayout out;
  out.entries_of.resize(num_blocks);
  out.row_start.assign(num_residuals + 1, 0);
  for (int k = 0; k < num_blocks; ++k) {
    const std::vector<int>& block_ids = registry.blocks_of(k);
    for (size_t slot = 0; slot < block_ids.size(); ++slot) {
      if (!asked[block_ids[slot]]) continue;
      const auto& columns = registry.free_columns()[block_ids[slot]];
      for (size_t i = 0; i < columns.size(); ++i) {
        if (columns[i] < 0) continue;
        out.entries_of[k].push_back(
            {renumbered[columns[i]], static_cast<int>(slot), static_cast<int>(i)});
      }
    }
    std::sort(out.entries_of[k].begin(), out.entries_of[k].end());
    for (int row = 0; row < registry.cost(k)->num_residuals(); ++row) {
      out.row_start[first_row[k] + row + 1] = static_cast<int>(out.entries_of[k].size());
    }
  }
  for (int row = 0; row < num_residuals; ++row) out.row_start[row + 1] += out.row_start[row];
  return out;
}

}  // namespace

bool SparseEvaluator::EvaluateColumns(const std::vector<int>& blocks, SparseJacobian* jacobian,
                                      std::vector<int>* columns) const {
  const std::vector<FreeParameter>& free = registry_.free_parameters();
  std::vector<bool> asked(static_cast<size_t>(registry_.num_blocks()), false);
  for (int b : blocks) asked.at(b) = true;
  std::vector<int> renumbered(free.size(), -1);
  columns->clear();
  for (size_t c = 0; c < free.size(); ++c) {
    if (!asked[free[c].block]) continue;
    renumbered[c] = static_cast<int>(columns->size());
    columns->push_back(static_cast<int>(c));
  }
  const ColumnLayout layout = LayOutColumns(registry_, asked, renumbered);
  std::vector<int> column_index(static_cast<size_t>(layout.row_start.back()));
  std::vector<double> entries(column_index.size());
  std::atomic<bool> valid{true};
  const int num_blocks = registry_.num_residual_blocks();
  tbb::parallel_for(tbb::blocked_range<int>(0, num_blocks, 64), [&](const auto& range) {
    BlockEvaluator block(registry_, layout_);
    for (int k = range.begin(); k != range.end() && valid; ++k) {
      if (layout.entries_of[k].empty()) continue;  // reads none of the blocks asked for
      const std::vector<int>& block_ids = registry_.blocks_of(k);
      block.AskSlotsOf(k, asked);
      if (!block.Evaluate(k, true)) {
        valid = false;
        break;
      }
      const int num_rows = static_cast<int>(block.residuals().size());
      for (int row = 0; row < num_rows; ++row) {
        int at = layout.row_start[registry_.residual_rows()[k] + row];
        for (const ColumnEntry& e : layout.entries_of[k]) {
          column_index[at] = e.column;
          entries[at++] = block.At(e.slot, row, registry_.block_size(block_ids[e.slot]), e.index);
        }
      }
    }
  });
  if (!valid) return false;
  *jacobian = Eigen::Map<const SparseJacobian>(
      registry_.num_residuals(), static_cast<Eigen::Index>(columns->size()),
      static_cast<Eigen::Index>(entries.size()), layout.row_start.data(), column_index.data(),
      entries.data());
  return true;
}

}  // namespace cellmetry
