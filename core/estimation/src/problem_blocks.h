// Problem's parameter and residual blocks (internal to the estimation layer): problem.cc builds
// and evaluates them, normal_equations.cc sums over them.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cellmetry/estimation/problem.h"

namespace cellmetry {

struct Problem::Block {
  std::string name;
  std::vector<Parameter> params;
  std::vector<double> values;
  bool used = false;
};

struct Problem::Residual {
  std::unique_ptr<ceres::CostFunction> cost;
  const std::vector<int>* blocks;  // one of Problem::block_lists_
};

// One residual block's evaluation, in buffers each thread reuses from block to block.
struct Problem::BlockEvaluation {
  std::vector<char> asked;                     // per slot: its Jacobian wanted (the caller's)
  std::vector<const double*> parameters;       // per slot
  std::vector<std::vector<double>> jacobians;  // per slot, row-major: rows x the block's size
  std::vector<double*> pointers;               // per slot; null where not asked
  std::vector<double> residuals;
  // Entry `index` of the slot's Jacobian in `row` (`width`: the slot's block size).
  double At(int slot, int row, int width, int index) const {
    return jacobians[slot][static_cast<size_t>(row) * width + index];
  }
};

}  // namespace cellmetry
