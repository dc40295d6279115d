// The R factor of a sparse Jacobian by QR of its row groups (r_factor.h).
#include "cellmetry/estimation/r_factor.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

#include "cellmetry/basics/dense_decompositions.h"
#include "column_patterns.h"

namespace cellmetry {
namespace {

// Rows that touch the same columns, gathered dense on those columns only.
struct RowGroup {
  std::vector<int> columns;  // ascending
  std::vector<int> rows;
};

std::vector<RowGroup> GroupRowsByColumns(const SparseJacobian& J) {
  ColumnPatterns patterns;
  std::vector<RowGroup> groups;
  const int* starts = J.outerIndexPtr();
  for (Eigen::Index row = 0; row < J.outerSize(); ++row) {
    const int count = starts[row + 1] - starts[row];
    if (count == 0) continue;  // a row of zeros adds nothing to J^T J
    const int g = patterns.GroupOf(J.innerIndexPtr() + starts[row], count);
    if (g == static_cast<int>(groups.size())) groups.push_back({patterns.groups()[g], {}});
    groups[static_cast<size_t>(g)].rows.push_back(static_cast<int>(row));
  }
  return groups;
}

// The upper triangle (at most `width` rows) of a dense block by Householder QR.
Eigen::MatrixXd Triangle(const Eigen::MatrixXd& block) {
  const Eigen::Index height = std::min(block.rows(), block.cols());
  if (block.rows() <= 1) return block;
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(block);
  return qr.matrixQR().topRows(height).triangularView<Eigen::Upper>();
}

// A piece of a group: its rows [begin, end), dense on the group's columns, reduced to a triangle.
Eigen::MatrixXd PieceTriangle(const SparseJacobian& J, const RowGroup& group, size_t begin,
                              size_t end) {
  const Eigen::Index width = static_cast<Eigen::Index>(group.columns.size());
  Eigen::MatrixXd block(static_cast<Eigen::Index>(end - begin), width);
  const double* values = J.valuePtr();
  const int* starts = J.outerIndexPtr();
  for (size_t k = begin; k < end; ++k) {
    const double* row = values + starts[group.rows[k]];  // the group's columns, in order
    const Eigen::Index r = static_cast<Eigen::Index>(k - begin);
    for (Eigen::Index c = 0; c < width; ++c) block(r, c) = row[c];
  }
  return Triangle(block);
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

// Rows per piece a group is split into: pieces are reduced on every core, each in cache (a
// 2,048 x 15 block is 240 kB), and a group's piece triangles are reduced once more on its own
// few columns before they meet the n-wide stack.
constexpr size_t kPieceRows = 2048;

}  // namespace

Eigen::MatrixXd RFactor(const SparseJacobian& J) {
  const Eigen::Index n = J.cols();
  if (n == 0) return Eigen::MatrixXd(0, 0);
  if (!J.isCompressed()) {  // the row reads below index J's arrays directly
    SparseJacobian compressed = J;
    compressed.makeCompressed();
    return RFactor(compressed);
  }
  const std::vector<RowGroup> groups = GroupRowsByColumns(J);
  struct Piece {
    size_t group, begin, end;
  };
  std::vector<Piece> pieces;
  for (size_t g = 0; g < groups.size(); ++g) {
    for (size_t begin = 0; begin < groups[g].rows.size(); begin += kPieceRows) {
      pieces.push_back({g, begin, std::min(begin + kPieceRows, groups[g].rows.size())});
    }
  }
  // Each piece into its own slot: the same bits whichever thread reduces it.
  std::vector<Eigen::MatrixXd> triangles(pieces.size());
  tbb::parallel_for(size_t{0}, pieces.size(), [&](size_t i) {
    const Piece& p = pieces[i];
    triangles[i] = PieceTriangle(J, groups[p.group], p.begin, p.end);
  });
  // Stacked group triangles are compressed whenever they pass 4n rows: memory O(n^2), whatever
  // the number of rows or groups.
  Eigen::MatrixXd stack = Eigen::MatrixXd::Zero(5 * n, n);
  int rows = 0;
  for (size_t i = 0; i < pieces.size();) {
    const RowGroup& group = groups[pieces[i].group];
    size_t end = i;
    Eigen::Index height = 0;
    while (end < pieces.size() && pieces[end].group == pieces[i].group) {
      height += triangles[end++].rows();
    }
    Eigen::MatrixXd group_stack(height, static_cast<Eigen::Index>(group.columns.size()));
    const bool several = end - i > 1;  // one piece's triangle is the group's already
    for (Eigen::Index at = 0; i < end; at += triangles[i++].rows()) {
      group_stack.middleRows(at, triangles[i].rows()) = triangles[i];
    }
    const Eigen::MatrixXd R = several ? Triangle(group_stack) : group_stack;
    if (rows + R.rows() > stack.rows()) rows = Compress(&stack, rows);
    for (Eigen::Index r = 0; r < R.rows(); ++r) {
      for (Eigen::Index c = 0; c < R.cols(); ++c) stack(rows + r, group.columns[c]) = R(r, c);
    }
    rows += static_cast<int>(R.rows());
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
