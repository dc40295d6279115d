// Problem::EvaluateNormalEquations (problem.h): J^T W J and J^T W r summed block by block.
//
// Each residual block's rows share its free columns (BuildSparseLayout's entries, in column
// order), so the block's k columns give a k x k outer product added to the n x n sum at those
// columns: the rows times k^2, never the m x n Jacobian. The blocks are split into fixed ranges
// summed in a fixed tree (tbb::parallel_deterministic_reduce), so the result's bits do not
// depend on the threads' timing: a fit reweighted with it answers the same on every run.
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <atomic>
#include <cstddef>

#include "cellmetry/estimation/problem.h"
#include "problem_blocks.h"

namespace cellmetry {
namespace {

// One range's sums, the lower triangle of the Hessian only (mirrored at the end).
struct PartialSums {
  double cost = 0.0;
  Eigen::VectorXd gradient;
  Eigen::MatrixXd hessian;
  explicit PartialSums(int n) : gradient(Eigen::VectorXd::Zero(n)),
                                hessian(Eigen::MatrixXd::Zero(n, n)) {}
  void Add(const PartialSums& other) {
    cost += other.cost;
    gradient += other.gradient;
    hessian += other.hessian;
  }
};

// The robust weight w = rho'(s) of a block and its cost term rho(s) (s = |r|^2).
void Weigh(const ceres::LossFunction* loss, double squared_norm, double* rho, double* weight) {
  if (loss == nullptr) {
    *rho = squared_norm;
    *weight = 1.0;
    return;
  }
  double values[3];
  loss->Evaluate(squared_norm, values);
  *rho = values[0];
  *weight = values[1];
}

}  // namespace

bool Problem::EvaluateNormalEquations(NormalEquations* out) const {
  const int n = num_free();
  const int num_blocks = static_cast<int>(evaluation_order_.size());
  std::atomic<bool> valid{true};
  // The range's blocks added to `sums` (buffers per call: a range is hundreds of blocks).
  auto add_range = [&](const tbb::blocked_range<int>& range, PartialSums* sums) {
    std::vector<const double*> parameters;
    std::vector<std::vector<double>> block_jacobians;
    std::vector<double*> jacobian_pointers;
    std::vector<double> residuals;
    Eigen::MatrixXd gathered;  // the block's rows x its free columns
    for (int k = range.begin(); k != range.end() && valid; ++k) {
      const auto& [cost, ids] = evaluation_order_[k];
      const std::vector<int>& block_ids = *ids;
      const int num_rows = cost->num_residuals();
      const int first = sparse_entry_start_[k], width = sparse_entry_start_[k + 1] - first;
      parameters.clear();
      block_jacobians.resize(block_ids.size());
      jacobian_pointers.assign(block_ids.size(), nullptr);  // no free entry: not asked for
      for (size_t slot = 0; slot < block_ids.size(); ++slot) {
        parameters.push_back(values(block_ids[slot]));
      }
      for (int e = first; e < first + width; ++e) {
        const int slot = sparse_entries_[e].slot;
        block_jacobians[slot].resize(static_cast<size_t>(num_rows) *
                                     blocks_[block_ids[slot]]->params.size());
        jacobian_pointers[slot] = block_jacobians[slot].data();
      }
      residuals.resize(num_rows);
      if (!cost->Evaluate(parameters.data(), residuals.data(), jacobian_pointers.data())) {
        valid = false;
        break;
      }
      const Eigen::Map<const Eigen::VectorXd> r(residuals.data(), num_rows);
      double rho = 0.0, weight = 0.0;
      Weigh(evaluation_losses_[k], r.squaredNorm(), &rho, &weight);
      sums->cost += 0.5 * rho;
      if (width == 0 || weight == 0.0) continue;
      gathered.resize(num_rows, width);
      for (int j = 0; j < width; ++j) {
        const SparseEntry& e = sparse_entries_[first + j];
        const int block_width = static_cast<int>(blocks_[block_ids[e.slot]]->params.size());
        for (int row = 0; row < num_rows; ++row) {
          gathered(row, j) = block_jacobians[e.slot][row * block_width + e.index];  // row-major
        }
      }
      for (int i = 0; i < width; ++i) {
        const int column_i = sparse_entries_[first + i].column;
        sums->gradient[column_i] += weight * gathered.col(i).dot(r);
        for (int j = 0; j <= i; ++j) {  // columns ascend: (i, j) is in the lower triangle
          sums->hessian(column_i, sparse_entries_[first + j].column) +=
              weight * gathered.col(i).dot(gathered.col(j));
        }
      }
    }
  };
  const PartialSums total = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int>(0, num_blocks, 512), PartialSums(n),
      [&](const tbb::blocked_range<int>& range, PartialSums sums) {
        add_range(range, &sums);
        return sums;
      },
      [](PartialSums a, const PartialSums& b) {
        a.Add(b);
        return a;
      });
  if (!valid) return false;
  out->cost = total.cost;
  out->gradient = total.gradient;
  out->hessian = total.hessian.selfadjointView<Eigen::Lower>();
  return true;
}

}  // namespace cellmetry
