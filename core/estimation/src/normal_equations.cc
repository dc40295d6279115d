// Problem::EvaluateNormalEquations (problem.h): J^T W J and J^T W r summed block by block.
//
// Each residual block's rows share its free columns (BuildSparseLayout's entries, in column
// order), so the block's k columns give a k x k outer product, summed densely with the other
// blocks of its column group and added to the n x n sum at those columns once per range: the
// rows times k^2, never the m x n Jacobian. The blocks are split into fixed ranges
// summed in a fixed tree (tbb::parallel_deterministic_reduce), so the result's bits do not
// depend on the threads' timing: a fit reweighted with it answers the same on every run.
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cstddef>

#include "cellmetry/estimation/problem.h"
#include "problem_blocks.h"

namespace cellmetry {
namespace {

// One range's sums, the upper triangle of the Hessian only (mirrored at the end).
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

// How a block enters the sums: its cost term rho(s) (s = |r|^2), its weight w = rho'(s) and
// the second-order term c = 2 rho''(s) of the loss, which makes the block's Hessian
// J^T (w I + c r r^T) J, the robust cost's own Gauss-Newton curvature (Triggs, McLauchlan,
// Hartley & Fitzgibbon 2000, "Bundle adjustment: a modern synthesis", sec. 4.3). Where that
// curvature is not positive along r (w + c s <= 0: a block far out on a redescending loss) c is
// 0 and the block keeps the reweighted w J^T J, so the sum stays positive semi-definite.
struct BlockWeight {
  double rho = 0.0, w = 1.0, c = 0.0;
};

BlockWeight Weigh(const ceres::LossFunction* loss, double squared_norm) {
  if (loss == nullptr) return {squared_norm, 1.0, 0.0};
  double values[3];
  loss->Evaluate(squared_norm, values);
  const double c = 2.0 * values[2];
  return {values[0], values[1], values[1] + c * squared_norm > 0.0 ? c : 0.0};
}

// The sums of one column group within a range, dense over the group's k columns: a block's
// rows are added with contiguous inner loops, and the group is scattered into the n x n sums
// once per range instead of once per block (on exp_a one evaluation 3.2 -> 2.6 ms, of which
// 2.0 ms are the cost functions: BM_NormalEquations against BM_SparseJacobian).
struct GroupSums {
  std::vector<double> hessian;   // k x k row-major, entries (i, j) with j <= i
  std::vector<double> gradient;  // k
  bool touched = false;
};

// A block's rows (row-major, rows x k) and residuals added to its group with its weight.
// `jr`: room for J^T r over the k columns.
void AddWeightedBlock(const double* jacobian, const double* residuals, int num_rows, int k,
                      const BlockWeight& weight, std::vector<double>* jr, GroupSums* group) {
  if (!group->touched) {
    group->hessian.assign(static_cast<size_t>(k) * k, 0.0);
    group->gradient.assign(k, 0.0);
    group->touched = true;
  }
  double* h = group->hessian.data();
  jr->assign(k, 0.0);
  for (int row = 0; row < num_rows; ++row) {
    const double* j_row = jacobian + row * k;
    for (int i = 0; i < k; ++i) {
      (*jr)[i] += j_row[i] * residuals[row];
      const double weighted = weight.w * j_row[i];
      double* h_row = h + i * k;
      for (int j = 0; j <= i; ++j) h_row[j] += weighted * j_row[j];
    }
  }
  for (int i = 0; i < k; ++i) {
    group->gradient[i] += weight.w * (*jr)[i];
    if (weight.c == 0.0) continue;
    const double weighted = weight.c * (*jr)[i];
    double* h_row = h + i * k;
    for (int j = 0; j <= i; ++j) h_row[j] += weighted * (*jr)[j];
  }
}

// A group's sums added to the n x n ones at its columns (ascending: (column j, column i) for
// j <= i is in the upper triangle of the column-major n x n), and cleared.
void ScatterGroup(const std::vector<int>& columns, GroupSums* group, PartialSums* sums) {
  const int k = static_cast<int>(columns.size());
  const Eigen::Index n = sums->hessian.rows();
  double* hessian = sums->hessian.data();
  for (int i = 0; i < k; ++i) {
    sums->gradient[columns[i]] += group->gradient[i];
    double* column_i = hessian + columns[i] * n;
    const double* h_row = group->hessian.data() + i * k;
    for (int j = 0; j <= i; ++j) column_i[columns[j]] += h_row[j];
  }
  group->touched = false;
}

}  // namespace

bool Problem::EvaluateNormalEquations(NormalEquations* out) const {
  const int n = num_free();
  const int num_blocks = static_cast<int>(evaluation_order_.size());
  std::atomic<bool> valid{true};
  // The range's blocks added to `sums` (buffers per call: a range is hundreds of blocks).
  auto add_range = [&](const tbb::blocked_range<int>& range, PartialSums* sums) {
    BlockEvaluation scratch;
    std::vector<GroupSums> groups(group_columns_.size());
    std::vector<double> gathered;  // the block's rows x its free columns, row-major
    std::vector<double> jr;
    for (int k = range.begin(); k != range.end() && valid; ++k) {
      const std::vector<int>& block_ids = *evaluation_order_[k].second;
      const int first = sparse_entry_start_[k], width = sparse_entry_start_[k + 1] - first;
      AskFreeSlots(k, &scratch);
      if (!EvaluateBlock(k, true, &scratch)) {
        valid = false;
        break;
      }
      const int num_rows = static_cast<int>(scratch.residuals.size());
      const std::vector<double>& residuals = scratch.residuals;
      const Eigen::Map<const Eigen::VectorXd> r(residuals.data(), num_rows);
      const BlockWeight weight = Weigh(evaluation_losses_[k], r.squaredNorm());
      sums->cost += 0.5 * weight.rho;
      if (width == 0 || (weight.w == 0.0 && weight.c == 0.0)) continue;
      gathered.resize(static_cast<size_t>(num_rows) * width);
      for (int j = 0; j < width; ++j) {
        const SparseEntry& e = sparse_entries_[first + j];
        const int block_width = static_cast<int>(blocks_[block_ids[e.slot]]->params.size());
        for (int row = 0; row < num_rows; ++row) {
          gathered[row * width + j] = scratch.At(e.slot, row, block_width, e.index);
        }
      }
      AddWeightedBlock(gathered.data(), residuals.data(), num_rows, width, weight, &jr,
                       &groups[column_group_[k]]);
    }
    for (size_t g = 0; g < groups.size(); ++g) {
      if (groups[g].touched) ScatterGroup(group_columns_[g], &groups[g], sums);
    }
  };
  // Ranges of at least 512 blocks and at most about 128 of them: each range holds an n x n sum
  // (1.7 MB at the 456 columns of bench_scale's largest cell), so their number is bounded.
  const int grain = std::max(512, num_blocks / 64);
  const PartialSums total = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int>(0, num_blocks, grain), PartialSums(n),
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
  out->hessian = total.hessian.selfadjointView<Eigen::Upper>();
  return true;
}

}  // namespace cellmetry
