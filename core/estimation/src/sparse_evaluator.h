// SparseEvaluator: a BlockRegistry's whitened residuals and sparse Jacobian with respect to its
// free parameters at the current values, without the robust loss (internal to the estimation
// layer; Problem::EvaluateSparse and EvaluateSparseColumns call it).
//
// Contract:
//   - Rows are the registry's residual rows, columns its free parameters (block_registry.h).
//     The Jacobian is written in place into compressed row storage whose row pointers Build()
//     fixed (evaluation_layout.h): no triplets, no copy.
//   - The cost functions are called directly on every core, a chunk of units per task. Ceres's
//     Evaluate builds a program of the chosen blocks at every call, which costs more than the
//     evaluation.
//   - A unit of blocks sharing a prediction (shared_prediction_cost.h) is predicted once: each
//     block's rows are D_i A from the one prediction.
//   - Gram rows (gram_rows.h): per unit the 3 rows L^T A, L L^T = sum_i D_i^T D_i, a block alone
//     standing for itself. Made only where they are at most a quarter of J's rows
//     (HasGramRows); else the caller's GramRows is left empty and J serves.
//   - The registry is only read; the evaluator holds no state between calls.
//   - False where a cost function failed (the Jacobian is then zero, the residuals untouched).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "cellmetry/estimation/block_registry.h"
#include "cellmetry/estimation/gram_rows.h"
#include "cellmetry/estimation/r_factor.h"
#include "evaluation_layout.h"

namespace cellmetry {

class BlockEvaluator;

class SparseEvaluator {
 public:
  SparseEvaluator(const BlockRegistry& registry, const EvaluationLayout& layout)
      : registry_(registry), layout_(layout) {}

  // The residuals and, where not null, the Jacobian and the Gram rows. Without `jacobian`, the
  // Gram rows alone, J never stored: only where HasGramRows() (throws std::logic_error else).
  bool Evaluate(Eigen::VectorXd* residuals, SparseJacobian* jacobian, GramRows* gram) const;
  bool HasGramRows() const;

  // The Jacobian's columns of the free entries of `blocks` alone (ids), in column order and
  // numbered from 0 (`columns`: each one's free-parameter index). Only the residual blocks that
  // read one of `blocks` are evaluated, and each differentiates only those; every residual has
  // its row, and rows of the blocks not evaluated are empty.
  bool EvaluateColumns(const std::vector<int>& blocks, SparseJacobian* jacobian,
                       std::vector<int>* columns) const;

 private:
  // Where one unit's rows go: residuals into `r`, its rows of J's compressed row storage when
  // `column_index` is not null, its Gram rows when `gram` is not.
  struct Output {
    double* r;
    int* column_index;  // null: no Jacobian
    double* entries;
    GramRows* gram = nullptr;  // with its first row per unit, then the end
    const int* gram_unit_row = nullptr;
  };

  // Unit u's one block, whose Gram rows are its own rows.
  bool EvaluateBlockRows(int u, BlockEvaluator* block, const Output& out) const;
  // Unit u's blocks from their one prediction (`tangent`: room for A).
  bool EvaluateSharedRows(int u, BlockEvaluator* block, std::vector<double>* tangent,
                          const Output& out) const;
  // Residual block k's Jacobian rows, as `block` holds them, into compressed rows at its free
  // columns: row i's entries from row_start[i].
  void WriteBlockRows(int k, const BlockEvaluator& block, const int* row_start, int* column_index,
                      double* entries) const;
  // The 3 Gram rows L^T A of unit u (L L^T = `information`, A = `tangent`, 3 x width row-major
  // at the unit's free columns).
  void AddGramRows(int u, const Eigen::Matrix3d& information, const double* tangent, int width,
                   const Output& out) const;
  // Sizes `gram` and returns each unit's first Gram row (then the end); empty, and `gram` left
  // empty, where they would be more than a quarter of J's rows.
  std::vector<int> LayOutGramRows(GramRows* gram) const;
  // The number of Gram rows (3 per unit sharing a prediction, a block's own rows otherwise)
  // and, with `unit_row`, each unit's first (then the end).
  int NumGramRows(std::vector<int>* unit_row) const;

  const BlockRegistry& registry_;
  const EvaluationLayout& layout_;
};

}  // namespace cellmetry
