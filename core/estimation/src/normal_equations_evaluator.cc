// NormalEquationsEvaluator (normal_equations_evaluator.h): J^T W J and J^T W r summed block by
// block, units of shared predictions through their prediction, chunks in a fixed tree
// (tbb::parallel_deterministic_reduce).
#include "normal_equations_evaluator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <vector>

#include "cellmetry/estimation/shared_prediction_cost.h"
#include "block_evaluator.h"
#include "evaluation_layout.h"

namespace cellmetry {
// Not anonymous: with internal linkage GCC inlines all of what follows into the one reduce body
// below, and BM_NormalEquations/exp_a took 6 % longer; as the library's own functions they stay
// out of line.
namespace normal_equations_sums {

// One range's sums, the upper triangle of the Hessian only (mirrored at the end).
struct PartialSums {
  double cost = 0.0;
  Eigen::VectorXd gradient;
  Eigen::MatrixXd hessian;
  explicit PartialSums(int n)
      : gradient(Eigen::VectorXd::Zero(n)), hessian(Eigen::MatrixXd::Zero(n, n)) {}
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
// once per range instead of once per block (BM_NormalEquations against BM_SparseJacobian shows
// what is left beyond the cost functions).
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

// What the blocks of a unit sharing one prediction add, before the prediction's tangent
// Jacobian A (3 x k) multiplies it in: with block i's residual r_i, dr_i / d tangent D_i and its
// weights, J_i = D_i A and the blocks' sums are
//   sum_i J_i^T (w_i I + c_i r_i r_i^T) J_i = A^T M A,  M = sum_i D_i^T (w_i I + c_i r_i r_i^T) D_i
//   sum_i w_i J_i^T r_i = A^T v,                        v = sum_i w_i D_i^T r_i
// the block-by-block sum regrouped (shared_prediction_cost.h): 3 x 3 work per block instead of
// k x k.
struct SharedSums {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  void Add(const Eigen::Vector3d& r, const Eigen::Matrix3d& D, const BlockWeight& weight) {
    const Eigen::Vector3d Dt_r = D.transpose() * r;
    M += weight.w * D.transpose() * D;
    if (weight.c != 0.0) M += weight.c * Dt_r * Dt_r.transpose();
    v += weight.w * Dt_r;
  }
};

// A^T M A and A^T v added to the unit's group (`tangent`: A, row-major, 3 x k).
void AddSharedUnit(const double* tangent, const SharedSums& sums, int k, std::vector<double>* ma,
                   GroupSums* group) {
  if (!group->touched) {
    group->hessian.assign(static_cast<size_t>(k) * k, 0.0);
    group->gradient.assign(k, 0.0);
    group->touched = true;
  }
  ma->resize(3 * static_cast<size_t>(k));  // M A, row-major
  for (int row = 0; row < 3; ++row) {
    for (int j = 0; j < k; ++j) {
      (*ma)[row * k + j] = sums.M(row, 0) * tangent[j] + sums.M(row, 1) * tangent[k + j] +
                           sums.M(row, 2) * tangent[2 * k + j];
    }
  }
  double* h = group->hessian.data();
  for (int i = 0; i < k; ++i) {
    const double a0 = tangent[i], a1 = tangent[k + i], a2 = tangent[2 * k + i];
    group->gradient[i] += a0 * sums.v[0] + a1 * sums.v[1] + a2 * sums.v[2];
    double* h_row = h + i * k;
    for (int j = 0; j <= i; ++j) {
      h_row[j] += a0 * (*ma)[j] + a1 * (*ma)[k + j] + a2 * (*ma)[2 * k + j];
    }
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

// One range of units summed into `sums`, with buffers reused from block to block; each column
// group's sums are scattered into `sums` when the range goes.
class RangeSums {
 public:
  RangeSums(const BlockRegistry& registry, const EvaluationLayout& layout, PartialSums* sums)
      : registry_(registry), layout_(layout), sums_(sums), block_(registry, layout),
        groups_(layout_.group_columns.size()) {}
  ~RangeSums() {
    for (size_t g = 0; g < groups_.size(); ++g) {
      if (groups_[g].touched) ScatterGroup(layout_.group_columns[g], &groups_[g], sums_);
    }
  }
  RangeSums(const RangeSums&) = delete;
  RangeSums& operator=(const RangeSums&) = delete;

  bool AddUnit(int u) {
    return layout_.SharesPrediction(u) ? AddSharedPrediction(u) : AddBlock(layout_.first_block(u));
  }

 private:
  // Residual block k evaluated and added with its loss's weights.
  bool AddBlock(int k) {
    block_.AskFreeSlots(k);
    if (!block_.Evaluate(k, true)) return false;
    const std::vector<double>& residuals = block_.residuals();
    const int num_rows = static_cast<int>(residuals.size());
    const Eigen::Map<const Eigen::VectorXd> r(residuals.data(), num_rows);
    const BlockWeight weight = Weigh(registry_.loss(k), r.squaredNorm());
    sums_->cost += 0.5 * weight.rho;
    const int width = block_.GatherFreeColumns(k, num_rows, &gathered_);
    if (width == 0 || (weight.w == 0.0 && weight.c == 0.0)) return true;
    AddWeightedBlock(gathered_.data(), residuals.data(), num_rows, width, weight, &jr_,
                     &groups_[layout_.column_group[k]]);
    return true;
  }

  // Unit u's prediction evaluated once, each of its blocks compared with it (SharedSums).
  bool AddSharedPrediction(int u) {
    const int first = layout_.first_block(u);
    block_.AskFreeSlots(first);
    Pose prediction;
    if (!block_.Predict(first, &prediction)) return false;
    SharedSums shared;
    Eigen::Vector3d r;
    Eigen::Matrix3d D;
    for (int i = layout_.unit_start[u]; i < layout_.unit_start[u + 1]; ++i) {
      const int k = layout_.unit_blocks[i];
      const auto* cost = static_cast<const SharedPredictionCost*>(registry_.cost(k));
      cost->Compare(prediction, r.data(), &D);
      const BlockWeight weight = Weigh(registry_.loss(k), r.squaredNorm());
      sums_->cost += 0.5 * weight.rho;
      if (weight.w != 0.0 || weight.c != 0.0) shared.Add(r, D, weight);
    }
    const int width = block_.GatherFreeColumns(first, 3, &gathered_);
    if (width > 0) {
      AddSharedUnit(gathered_.data(), shared, width, &jr_, &groups_[layout_.column_group[first]]);
    }
    return true;
  }

  const BlockRegistry& registry_;
  const EvaluationLayout& layout_;
  PartialSums* sums_;
  BlockEvaluator block_;
  std::vector<GroupSums> groups_;
  std::vector<double> gathered_;  // a block's rows x its free columns, row-major
  std::vector<double> jr_;        // J^T r of a block, or M A of a unit
};

}  // namespace normal_equations_sums

using normal_equations_sums::PartialSums;
using normal_equations_sums::RangeSums;

bool NormalEquationsEvaluator::Evaluate(NormalEquations* out) const {
  const EvaluationLayout& layout = layout_;
  const int n = registry_.num_free();
  std::atomic<bool> valid{true};
  // Each chunk of units summed on its own, the chunks' sums added in a fixed tree.
  auto add_chunks = [&](const tbb::blocked_range<int>& chunks, PartialSums* sums) {
    RangeSums range(registry_, layout_, sums);  // scattered into `sums` when it goes
    const int end = layout.chunk_start[chunks.end()];
    for (int u = layout.chunk_start[chunks.begin()]; u != end && valid; ++u) {
      if (!range.AddUnit(u)) valid = false;
    }
  };
  const PartialSums total = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<int>(0, layout.num_chunks(), 1), PartialSums(n),
      [&](const tbb::blocked_range<int>& chunks, PartialSums sums) {
        add_chunks(chunks, &sums);
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
