// Problem's shared predictions (problem.h, shared_prediction_cost.h): which residual blocks
// predict the same, and one prediction evaluated for them (the normal equations' use of it is
// in normal_equations.cc).
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <unordered_map>
#include <vector>

#include "cellmetry/estimation/problem.h"
#include "cellmetry/estimation/shared_prediction_cost.h"
#include "problem_blocks.h"

namespace cellmetry {

namespace {

// A unit's blocks are summed by one thread: a static camera's world-tag observations (5,000 on
// bench_scale's factory cell, all of them after the robots' blocks) in one unit were one
// thread's serial tail. Beyond this many blocks the prediction is evaluated again for the next
// ones, once per 256 comparisons.
constexpr int kMaxUnitBlocks = 256;

}  // namespace

void Problem::BuildPredictionUnits() {
  const int num_blocks = static_cast<int>(evaluation_order_.size());
  // Each block's unit: a new one at a block that shares nothing or at the first of its key
  // and parameter blocks (so units are in the order of their first block).
  std::vector<int> unit_of_block(num_blocks);
  std::vector<int> unit_size;
  // Per key, its latest unit and that unit's parameter blocks: a block with the key over other
  // blocks starts a unit of its own (shared by the blocks after it that match it).
  std::unordered_map<const void*, int> unit_of_key;
  std::vector<const std::vector<int>*> blocks_of_unit;
  for (int k = 0; k < num_blocks; ++k) {
    const auto* shared = dynamic_cast<const SharedPredictionCost*>(evaluation_order_[k].first);
    const void* key = shared ? shared->prediction_key() : nullptr;
    const std::vector<int>* block_ids = evaluation_order_[k].second;
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
  const int num_units = static_cast<int>(unit_size.size());
  unit_start_.assign(num_units + 1, 0);
  for (int u = 0; u < num_units; ++u) {
    unit_start_[u + 1] = unit_start_[u] + unit_size[u];
  }
  // Chunks of at least 256 blocks and at most about 64 of them (the normal equations hold an
  // n x n sum per chunk: 1.7 MB at the 456 columns of bench_scale's largest cell).
  const int chunk_blocks = std::max(256, num_blocks / 64);
  chunk_start_.assign(1, 0);
  for (int u = 0, in_chunk = 0; u < num_units; ++u) {
    in_chunk += unit_size[u];
    if (in_chunk >= chunk_blocks || u + 1 == num_units) {
      chunk_start_.push_back(u + 1);
      in_chunk = 0;
    }
  }
  unit_blocks_.resize(num_blocks);
  std::vector<int> next(unit_start_.begin(), unit_start_.end() - 1);
  for (int k = 0; k < num_blocks; ++k) unit_blocks_[next[unit_of_block[k]]++] = k;
}

bool Problem::PredictBlock(int k, BlockEvaluation* scratch, Pose* prediction) const {
  const auto* cost = static_cast<const SharedPredictionCost*>(evaluation_order_[k].first);
  PrepareSlots(k, 3, /*with_jacobians=*/true, scratch);  // the tangent's 3 rows, where asked
  return cost->Predict(scratch->parameters.data(), prediction, scratch->pointers.data());
}

bool Problem::EvaluateSharedRows(int u, BlockEvaluation* scratch,
                                 const SparseOutput& out) const {
  const bool with_jacobian = out.column_index != nullptr || out.gram != nullptr;
  const int first = unit_blocks_[unit_start_[u]];
  AskFreeSlots(first, scratch);
  if (!with_jacobian) std::fill(scratch->asked.begin(), scratch->asked.end(), 0);
  Pose prediction;
  if (!PredictBlock(first, scratch, &prediction)) return false;
  // A at the unit's free columns (every block of the unit has the same), row-major 3 x width.
  const int entry = block_entries_[first].begin;
  std::vector<double>& tangent = scratch->residuals;  // free here: the rows go straight to `out`
  const int width = with_jacobian ? GatherFreeColumns(first, 3, *scratch, &tangent) : 0;
  Eigen::Matrix3d D;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();  // sum of D^T D, for the Gram rows
  for (int i = unit_start_[u]; i < unit_start_[u + 1]; ++i) {
    const int k = unit_blocks_[i];
    static_cast<const SharedPredictionCost*>(evaluation_order_[k].first)
        ->Compare(prediction, out.r + rows_[k], with_jacobian ? &D : nullptr);
    if (!with_jacobian) continue;
    if (out.gram) information.noalias() += D.transpose() * D;
    if (out.column_index == nullptr) continue;  // the Gram rows alone
    for (int row = 0; row < 3; ++row) {  // row `row` of D A
      int at = sparse_row_start_[rows_[k] + row];
      for (int j = 0; j < width; ++j) {
        out.column_index[at] = sparse_entries_[entry + j].column;
        out.entries[at++] = D(row, 0) * tangent[j] + D(row, 1) * tangent[width + j] +
                            D(row, 2) * tangent[2 * width + j];
      }
    }
  }
  if (out.gram) AddGramRows(u, information, tangent.data(), width, out);
  return true;
}

void Problem::AddGramRows(int u, const Eigen::Matrix3d& information, const double* tangent,
                          int width, const SparseOutput& out) const {
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
  const int first = unit_blocks_[unit_start_[u]];
  const int entry = block_entries_[first].begin;
  for (int row = 0; row < 3; ++row) {
    const int gram_row = out.gram_unit_row[u] + row;
    int at = out.gram->rows.outerIndexPtr()[gram_row];
    for (int j = 0; j < width; ++j) {
      out.gram->rows.innerIndexPtr()[at] = sparse_entries_[entry + j].column;
      out.gram->rows.valuePtr()[at++] = L_t(row, 0) * tangent[j] +
                                        L_t(row, 1) * tangent[width + j] +
                                        L_t(row, 2) * tangent[2 * width + j];
    }
    out.gram->block[static_cast<size_t>(gram_row)] = first;
  }
}

}  // namespace cellmetry
