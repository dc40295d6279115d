// The R factor of a sparse Jacobian by QR of its row groups (r_factor.h).
#include "cellmetry/estimation/r_factor.h"

#include <Eigen/QR>
#include <map>
#include <vector>

namespace cellmetry {
namespace {

// Rows that touch the same columns, gathered dense on those columns only.
struct RowGroup {
  std::vector<int> columns;   // ascending
  std::vector<int> rows;
};

std::vector<RowGroup> GroupRowsByColumns(const SparseJacobian& J) {
  std::map<std::vector<int>, int> index;  // columns -> group
  std::vector<RowGroup> groups;
  std::vector<int> columns, last_columns;
  int last_group = -1;
  for (Eigen::Index row = 0; row < J.outerSize(); ++row) {
    columns.clear();
    for (SparseJacobian::InnerIterator it(J, row); it; ++it) {
      columns.push_back(static_cast<int>(it.col()));
    }
    if (columns.empty()) continue;  // a row of zeros adds nothing to J^T J
    if (last_group < 0 || columns != last_columns) {  // a residual block's rows come together
      const auto [it, added] = index.emplace(columns, static_cast<int>(groups.size()));
      if (added) groups.push_back({columns, {}});
      last_group = it->second;
      last_columns = columns;
    }
    groups[last_group].rows.push_back(static_cast<int>(row));
  }
  return groups;
}

// The triangular factor of a group's dense block, scattered into `stack` at row `at`.
int AppendGroupR(const SparseJacobian& J, const RowGroup& group, Eigen::MatrixXd* stack, int at) {
  const int width = static_cast<int>(group.columns.size());
  Eigen::MatrixXd block =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(group.rows.size()), width);
  for (size_t k = 0; k < group.rows.size(); ++k) {
    int c = 0;
    for (SparseJacobian::InnerIterator it(J, group.rows[k]); it; ++it, ++c) {
      block(static_cast<Eigen::Index>(k), c) = it.value();  // same column order as group.columns
    }
  }
  const int height = std::min<int>(static_cast<int>(group.rows.size()), width);
  Eigen::MatrixXd R = block;
  if (block.rows() > 1) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(block);
    R = qr.matrixQR().topRows(height).triangularView<Eigen::Upper>();
  }
  for (int i = 0; i < height; ++i) {
    for (int c = 0; c < width; ++c) (*stack)(at + i, group.columns[c]) = R(i, c);
  }
  return at + height;
}

// Replaces the first `rows` rows of `stack` by their n x n triangular factor.
int Compress(Eigen::MatrixXd* stack, int rows) {
  const Eigen::Index n = stack->cols();
  if (rows <= n) return rows;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(stack->topRows(rows));
  stack->topRows(rows).setZero();
  stack->topRows(n) = qr.matrixQR().topRows(n).triangularView<Eigen::Upper>();
  return static_cast<int>(n);
}

}  // namespace

Eigen::MatrixXd RFactor(const SparseJacobian& J) {
  const Eigen::Index n = J.cols();
  if (n == 0) return Eigen::MatrixXd(0, 0);
  // Stacked group factors are compressed whenever they pass 4n rows: memory O(n^2), whatever
  // the number of rows or groups.
  Eigen::MatrixXd stack = Eigen::MatrixXd::Zero(5 * n, n);
  int rows = 0;
  for (const RowGroup& group : GroupRowsByColumns(J)) {
    if (rows + static_cast<Eigen::Index>(group.columns.size()) > stack.rows()) {
      rows = Compress(&stack, rows);
    }
    rows = AppendGroupR(J, group, &stack, rows);
  }
  rows = Compress(&stack, rows);
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(n, n);
  R.topRows(std::min<Eigen::Index>(rows, n)) = stack.topRows(std::min<Eigen::Index>(rows, n));
  return R;
}

Eigen::VectorXd ColumnNorms(const SparseJacobian& J) {
  Eigen::VectorXd squared = Eigen::VectorXd::Zero(J.cols());
  for (Eigen::Index row = 0; row < J.outerSize(); ++row) {
    for (SparseJacobian::InnerIterator it(J, row); it; ++it) {
      squared[it.col()] += it.value() * it.value();
    }
  }
  return squared.cwiseSqrt();
}

}  // namespace cellmetry
