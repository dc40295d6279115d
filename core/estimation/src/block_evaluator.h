// BlockEvaluator: one residual block of a BlockRegistry evaluated by calling its cost function
// directly, in buffers one thread reuses from block to block (internal to the estimation layer):
// the inner step of the sparse and the normal-equations evaluators.
//
// A block's Jacobian is asked for per slot (each parameter block it reads): an Ask call marks
// the slots, Evaluate() or Predict() fills the asked slots' Jacobians (row-major, the block's
// rows x the slot's block size) and passes null for the others, so an automatic-differentiation
// cost seeds only what is asked. Once the buffers have grown to the largest block nothing is
// allocated, and nothing here is virtual but the cost function's own call: the evaluations run
// it tens of thousands of times per pass. One BlockEvaluator per thread; the registry is only
// read.
#pragma once

#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/estimation/block_registry.h"
#include "evaluation_layout.h"

namespace cellmetry {

class BlockEvaluator {
 public:
  BlockEvaluator(const BlockRegistry& registry, const EvaluationLayout& layout)
      : registry_(registry), layout_(layout) {}

  // Marks the slots of residual block k that hold a free entry.
  void AskFreeSlots(int k);
  // Marks the slots of residual block k whose parameter block `asked_blocks` marks (by id).
  void AskSlotsOf(int k, const std::vector<bool>& asked_blocks);
  // Marks none of residual block k's slots.
  void AskNone(int k) { asked_.assign(registry_.blocks_of(k).size(), 0); }

  // Residual block k's residuals and, with `with_jacobians`, the asked slots' Jacobians. False
  // if its cost failed.
  bool Evaluate(int k, bool with_jacobians);
  // The shared prediction of residual block k (its cost a SharedPredictionCost) and, for the
  // asked slots, its tangent Jacobians (3 rows). False if it failed.
  bool Predict(int k, Pose* prediction);

  const std::vector<double>& residuals() const { return residuals_; }
  // Entry `index` of the Jacobian of `slot` in `row` (`width`: the slot's block size).
  double At(int slot, int row, int width, int index) const {
    return jacobians_[slot][static_cast<size_t>(row) * width + index];
  }
  // The first `num_rows` rows of residual block k's Jacobian, as the last Evaluate or Predict
  // left them, at its free columns (in column order) into `rows`, row-major; returns the number
  // of columns.
  int GatherFreeColumns(int k, int num_rows, std::vector<double>* rows) const;

 private:
  // Points the parameters at residual block k's blocks and, with `with_jacobians`, gives each
  // asked slot room for `num_rows` rows of its Jacobian.
  void PrepareSlots(int k, int num_rows, bool with_jacobians);

  const BlockRegistry& registry_;
  const EvaluationLayout& layout_;
  std::vector<char> asked_;                     // per slot: its Jacobian wanted
  std::vector<const double*> parameters_;       // per slot
  std::vector<std::vector<double>> jacobians_;  // per slot, row-major: rows x the block's size
  std::vector<double*> pointers_;               // per slot; null where not asked
  std::vector<double> residuals_;
};

}  // namespace cellmetry
