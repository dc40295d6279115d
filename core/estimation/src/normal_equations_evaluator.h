// NormalEquationsEvaluator: a BlockRegistry's normal equations (normal_equations.h) summed block
// by block on every core without storing J (internal to the estimation layer;
// Problem::EvaluateNormalEquations calls it).
//
// Contract:
//   - For a cell's few dozen free parameters and tens of thousands of residual blocks: what an
//     iteration of a reweighted fit needs, at a fraction of a sparse J's cost. Each block's k
//     free columns give a k x k outer product, summed densely with the other blocks of its
//     column group and added to the n x n sum once per chunk: the rows times k^2, never m x n.
//   - A unit of blocks sharing a prediction is summed through it: A^T M A and A^T v with
//     M = sum_i D_i^T (w_i I + c_i r_i r_i^T) D_i and v = sum_i w_i D_i^T r_i, each block with
//     its own robust loss (the block-by-block sum, regrouped).
//   - The sum's order is fixed: the layout's chunks (evaluation_layout.h) are summed in a fixed
//     tree, so the result's bits do not depend on the threads' timing, and a fit reweighted with
//     it answers the same on every run.
//   - The registry is only read. False where a cost function failed.
#pragma once

#include "cellmetry/estimation/block_registry.h"
#include "cellmetry/estimation/normal_equations.h"
#include "evaluation_layout.h"

namespace cellmetry {

class NormalEquationsEvaluator {
 public:
  NormalEquationsEvaluator(const BlockRegistry& registry, const EvaluationLayout& layout)
      : registry_(registry), layout_(layout) {}

  bool Evaluate(NormalEquations* out) const;

 private:
  const BlockRegistry& registry_;
  const EvaluationLayout& layout_;
};

}  // namespace cellmetry
