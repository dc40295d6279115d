// The variance of a leave-one-group-out estimate's difference from the full one
// (left_out_difference.h).
#include "cellmetry/estimation/left_out_difference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <Eigen/Dense>

#include "cellmetry/basics/dense_decompositions.h"

namespace cellmetry {
namespace {

// Each residual block's cluster as an index: the clusters with an id first, in id order (so
// that neighbours in capture order are neighbours here), then each block without one alone.
struct ClusterIndex {
  std::vector<int> of_block;
  int ordered = 0;  // how many lead (the ones with an id)
  int total = 0;
};

ClusterIndex IndexClusters(const std::vector<int>& cluster_of_block, size_t blocks) {
  ClusterIndex out;
  std::map<int, int> index;
  for (size_t b = 0; b < blocks; ++b) {
    if (b < cluster_of_block.size() && cluster_of_block[b] >= 0) index[cluster_of_block[b]];
  }
  for (auto& [id, k] : index) k = out.ordered++;
  out.total = out.ordered;
  out.of_block.resize(blocks);
  for (size_t b = 0; b < blocks; ++b) {
    const bool has_id = b < cluster_of_block.size() && cluster_of_block[b] >= 0;
    out.of_block[b] = has_id ? index.at(cluster_of_block[b]) : out.total++;
  }
  return out;
}

// Scores per cluster (clusters x columns) and J^T J, over the rows of the blocks `in` accepts.
template <typename Accept>
void ScoresAndInformation(const Problem& problem, const Linearization& at,
                          const ClusterIndex& clusters, Accept in, Eigen::MatrixXd* scores,
                          Eigen::MatrixXd* information) {
  const int n = problem.num_free();
  const auto& rows = problem.residual_rows();
  const int num_rows = static_cast<int>(at.residuals.size());
  scores->setZero(clusters.total, n);
  information->setZero(n, n);
  for (size_t b = 0; b < rows.size(); ++b) {
    if (!in(b)) continue;
    const int k = clusters.of_block[b];
    const int end = b + 1 < rows.size() ? rows[b + 1] : num_rows;
    for (int row = rows[b]; row < end; ++row) {
      for (SparseJacobian::InnerIterator a(at.jacobian, row); a; ++a) {
        (*scores)(k, a.col()) += a.value() * at.residuals[row];
        for (SparseJacobian::InnerIterator c(at.jacobian, row); c; ++c) {
          (*information)(a.col(), c.col()) += a.value() * c.value();
        }
      }
    }
  }
}

// (A + priors)^-1 on the columns the rows determine, zero elsewhere; `determined` says which.
// A column is undetermined where A's diagonal is below `tolerance^2` of the full information's
// (no row of the rest touches it), or where, column-scaled, the rest leaves it in a direction
// whose eigenvalue is below tolerance^2 of the largest (the singular-value test of
// FindDegenerateColumns, on J^T J).
Eigen::MatrixXd DeterminedInverse(const Eigen::MatrixXd& A, const Eigen::VectorXd& full_diagonal,
                                  double tolerance, std::vector<bool>* determined) {
  const Eigen::Index n = A.rows();
  determined->assign(static_cast<size_t>(n), false);
  std::vector<int> columns;
  for (Eigen::Index j = 0; j < n; ++j) {
    if (A(j, j) > tolerance * tolerance * full_diagonal[j] && A(j, j) > 0.0) {
      columns.push_back(static_cast<int>(j));
    }
  }
  Eigen::MatrixXd inverse = Eigen::MatrixXd::Zero(n, n);
  const Eigen::Index m = static_cast<Eigen::Index>(columns.size());
  if (m == 0) return inverse;
  Eigen::VectorXd scale(m);
  Eigen::MatrixXd scaled(m, m);
  for (Eigen::Index i = 0; i < m; ++i) scale[i] = 1.0 / std::sqrt(A(columns[i], columns[i]));
  for (Eigen::Index i = 0; i < m; ++i) {
    for (Eigen::Index k = 0; k < m; ++k) {
      scaled(i, k) = A(columns[i], columns[k]) * scale[i] * scale[k];
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scaled);
  const Eigen::VectorXd& lambda = eigen.eigenvalues();
  const double largest = lambda.maxCoeff();
  Eigen::VectorXd inverse_lambda = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd weak = Eigen::VectorXd::Zero(m);  // each column's share of dropped directions
  for (Eigen::Index i = 0; i < m; ++i) {
    if (lambda[i] > tolerance * tolerance * largest) {
      inverse_lambda[i] = 1.0 / lambda[i];
    } else {
      weak += eigen.eigenvectors().col(i).cwiseAbs2();
    }
  }
  const Eigen::MatrixXd& V = eigen.eigenvectors();
  const Eigen::MatrixXd scaled_inverse = V * inverse_lambda.asDiagonal() * V.transpose();
  for (Eigen::Index i = 0; i < m; ++i) {
    (*determined)[static_cast<size_t>(columns[i])] = weak[i] < 0.01;
    for (Eigen::Index k = 0; k < m; ++k) {
      inverse(columns[i], columns[k]) = scaled_inverse(i, k) * scale[i] * scale[k];
    }
  }
  return inverse;
}

// Per column, the serial-cluster sandwich variance of the per-cluster terms `terms` (clusters x
// columns): the ordered clusters' Bartlett-weighted cross products up to `lag`, as
// SerialClusterRobustCovariance, and the small-sample factor G / (G - 1).
Eigen::VectorXd SerialVariance(const Eigen::MatrixXd& terms, int ordered, int lag) {
  Eigen::VectorXd variance = terms.colwise().squaredNorm().transpose();
  for (int l = 1; l <= lag && l < ordered; ++l) {
    const double weight = 1.0 - l / (lag + 1.0);
    const Eigen::Index span = ordered - l;
    variance +=
        2.0 * weight *
        (terms.topRows(span).cwiseProduct(terms.middleRows(l, span))).colwise().sum().transpose();
  }
  const double G = static_cast<double>(terms.rows());
  return variance * (G > 1 ? G / (G - 1) : 1.0);
}

}  // namespace

std::vector<Eigen::VectorXd> LeftOutDifferenceVariance(
    const Problem& problem, const Linearization& at, const std::vector<int>& group_of_block,
    const std::vector<int>& cluster_of_block, const Uncertainty& full,
    const std::vector<LeftOutGroup>& left_out, double tolerance) {
  std::vector<Eigen::VectorXd> out;
  const int n = problem.num_free();
  if (!at.valid || n == 0) return out;
  const size_t blocks = problem.residual_rows().size();
  const ClusterIndex clusters = IndexClusters(cluster_of_block, blocks);
  auto group_of = [&](size_t b) { return b < group_of_block.size() ? group_of_block[b] : -1; };
  Eigen::MatrixXd scores, information;
  ScoresAndInformation(
      problem, at, clusters, [](size_t) { return true; }, &scores, &information);
  // B from this linearization, not the fit's own: the two turn frames about the same reference
  // rotations only where the fit's start was its answer.
  const Eigen::VectorXd full_diagonal = information.diagonal();
  std::vector<bool> full_determined;
  const Eigen::MatrixXd B =
      DeterminedInverse(information, full_diagonal, tolerance, &full_determined);
  const Eigen::MatrixXd full_terms = scores * B;  // row k: (B s_k)^T
  for (const LeftOutGroup& g : left_out) {
    Eigen::MatrixXd group_scores, group_information;
    ScoresAndInformation(
        problem, at, clusters, [&](size_t b) { return group_of(b) == g.group; }, &group_scores,
        &group_information);
    Eigen::MatrixXd rest = information - group_information;
    for (const auto& [column, sigma] : g.added_prior_sigma) {
      rest(column, column) += 1.0 / (sigma * sigma);
    }
    std::vector<bool> determined;
    const Eigen::MatrixXd B_g = DeterminedInverse(rest, full_diagonal, tolerance, &determined);
    // Row k: d_k^T = (B s_k - B_g (s_k - s_kg))^T; the difference is theta_{-g} - theta, whose
    // terms carry the opposite sign of these, which a variance does not see.
    const Eigen::MatrixXd terms = full_terms - (scores - group_scores) * B_g;
    Eigen::VectorXd variance = SerialVariance(terms, clusters.ordered, full.correlated_poses);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double model = full.scale * (B_g(i, i) - B(i, i));
      variance[i] = std::max(variance[i], model);
      for (const auto& [column, sigma] : g.added_prior_sigma) {
        variance[i] += B_g(i, column) * B_g(i, column) / (sigma * sigma);
      }
      if (!determined[static_cast<size_t>(i)]) {
        variance[i] = std::numeric_limits<double>::quiet_NaN();
      }
    }
    out.push_back(variance);
  }
  return out;
}

}  // namespace cellmetry
