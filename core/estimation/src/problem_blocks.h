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
  std::vector<int> blocks;
};

}  // namespace cellmetry
