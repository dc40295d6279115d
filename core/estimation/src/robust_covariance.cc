// The cluster-robust covariance and the jackknife spread (robust_covariance.h).
#include "cellmetry/estimation/robust_covariance.h"

#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <map>

#include "cellmetry/basics/statistics.h"

namespace cellmetry {

Eigen::MatrixXd ClusterRobustCovariance(const Problem& problem, const Linearization& at,
                                        const std::vector<int>& cluster_of_block,
                                        const Uncertainty& model) {
  const int n = problem.num_free();
  if (n == 0 || !at.valid) return Eigen::MatrixXd::Zero(0, 0);
  const Eigen::VectorXd& r = at.residuals;
  const SparseJacobian& J = at.jacobian;
  // Score of each cluster: J_g^T r_g.
  std::map<int, Eigen::VectorXd> score;
  const auto& rows = problem.residual_rows();
  int own = -1;  // negative ids for blocks that are their own cluster
  for (size_t b = 0; b < rows.size(); ++b) {
    const int end = b + 1 < rows.size() ? rows[b + 1] : static_cast<int>(r.size());
    const int g = b < cluster_of_block.size() && cluster_of_block[b] >= 0 ? cluster_of_block[b]
                                                                          : own--;
    const Eigen::VectorXd s = J.middleRows(rows[b], end - rows[b]).transpose() *
                              r.segment(rows[b], end - rows[b]);
    auto it = score.find(g);
    if (it == score.end()) {
      score.emplace(g, s);
    } else {
      it->second += s;
    }
  }
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(n, n);
  for (const auto& [g, s] : score) meat += s * s.transpose();
  const double G = static_cast<double>(score.size());
  const Eigen::MatrixXd bread = model.covariance / model.scale;  // (J^T J)^-1
  return bread * meat * bread * (G > 1 ? G / (G - 1) : 1.0);
}

void CombineUncertainty(const Eigen::MatrixXd& cluster, const Jackknife& jackknife,
                        Uncertainty* u, double quantile) {
  const Eigen::Index n = u->sigma.size();
  u->sigma_model = u->sigma;
  u->sigma_cluster = cluster.size() == n * n ? Eigen::VectorXd(cluster.diagonal().cwiseMax(0.0).cwiseSqrt())
                                             : Eigen::VectorXd(Eigen::VectorXd::Zero(n));
  u->sigma_statistical = u->sigma_model.cwiseMax(u->sigma_cluster);
  u->sigma_systematic = Eigen::VectorXd::Zero(n);
  if (jackknife.variance.size() == n) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const int g = jackknife.groups[i];
      if (g < 2) continue;
      const double statistical = u->sigma_statistical[i] * u->sigma_statistical[i];
      const double chance = ChiSquareQuantile(quantile, g - 1) / (g - 1);
      if (jackknife.variance[i] <= chance * statistical) continue;
      u->sigma_systematic[i] = std::sqrt(jackknife.variance[i] - statistical);
    }
  }
  u->sigma = (u->sigma_statistical.cwiseAbs2() + u->sigma_systematic.cwiseAbs2()).cwiseSqrt();
}

Jackknife JackknifeSpread(const std::vector<Eigen::VectorXd>& values) {
  Jackknife out;
  if (values.empty()) return out;
  const Eigen::Index n = values.front().size();
  out.variance = Eigen::VectorXd::Zero(n);
  out.groups = Eigen::VectorXi::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    double sum = 0.0;
    int count = 0;
    for (const auto& v : values) {
      if (std::isnan(v[i])) continue;
      sum += v[i];
      ++count;
    }
    out.groups[i] = count;
    if (count < 2) continue;
    const double mean = sum / count;
    double ss = 0.0;
    for (const auto& v : values) {
      if (!std::isnan(v[i])) ss += (v[i] - mean) * (v[i] - mean);
    }
    out.variance[i] = (count - 1.0) / count * ss;
  }
  return out;
}

namespace {

// J and r without the rows of the residual blocks in group `left_out`.
void WithoutGroup(const Problem& problem, const Linearization& at,
                  const std::vector<int>& group_of_block, int left_out, SparseJacobian* J,
                  Eigen::VectorXd* r) {
  const auto& rows = problem.residual_rows();
  const int num_rows = static_cast<int>(at.residuals.size());
  std::vector<int> kept;
  for (size_t b = 0; b < rows.size(); ++b) {
    if (b < group_of_block.size() && group_of_block[b] == left_out) continue;
    const int end = b + 1 < rows.size() ? rows[b + 1] : num_rows;
    for (int row = rows[b]; row < end; ++row) kept.push_back(row);
  }
  *J = SparseJacobian(static_cast<Eigen::Index>(kept.size()), at.jacobian.cols());
  J->reserve(Eigen::VectorXi::Constant(static_cast<int>(kept.size()),
                                       static_cast<int>(at.jacobian.cols())));
  r->resize(static_cast<Eigen::Index>(kept.size()));
  for (size_t k = 0; k < kept.size(); ++k) {
    (*r)[static_cast<Eigen::Index>(k)] = at.residuals[kept[k]];
    for (SparseJacobian::InnerIterator it(at.jacobian, kept[k]); it; ++it) {
      J->insert(static_cast<Eigen::Index>(k), it.col()) = it.value();
    }
  }
  J->makeCompressed();
}

// argmin_d |J d + r|^2 over the columns J determines at `tolerance`; NaN elsewhere. Solved on
// the column-scaled R factor's SVD, like the covariance.
Eigen::VectorXd GaussNewtonStep(const SparseJacobian& J, const Eigen::VectorXd& r,
                                double tolerance) {
  const Eigen::Index n = J.cols();
  const Eigen::MatrixXd R = RFactor(J);
  const Eigen::VectorXd norms = ColumnNorms(J);
  std::vector<bool> determined(static_cast<size_t>(n), true);
  for (const DegenerateColumn& c : FindDegenerateColumns(R, norms, tolerance)) {
    determined[static_cast<size_t>(c.column)] = false;
  }
  std::vector<int> columns;
  for (int j = 0; j < n; ++j) {
    if (determined[static_cast<size_t>(j)]) columns.push_back(j);
  }
  Eigen::VectorXd step = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  if (columns.empty()) return step;
  const Eigen::Index m = static_cast<Eigen::Index>(columns.size());
  Eigen::MatrixXd scaled(R.rows(), m);
  for (Eigen::Index k = 0; k < m; ++k) scaled.col(k) = R.col(columns[k]) / norms[columns[k]];
  const Eigen::VectorXd gradient = J.transpose() * r;  // J^T r over every column
  Eigen::VectorXd scaled_gradient(m);
  for (Eigen::Index k = 0; k < m; ++k) scaled_gradient[k] = gradient[columns[k]] / norms[columns[k]];
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinV);
  const Eigen::VectorXd s = svd.singularValues();
  Eigen::VectorXd inv_s2 = Eigen::VectorXd::Zero(s.size());
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (s[i] > 1e-14 * s[0]) inv_s2[i] = 1.0 / (s[i] * s[i]);
  }
  const Eigen::MatrixXd& V = svd.matrixV();
  const Eigen::VectorXd scaled_step = -(V * (inv_s2.asDiagonal() * (V.transpose() * scaled_gradient)));
  for (Eigen::Index k = 0; k < m; ++k) step[columns[k]] = scaled_step[k] / norms[columns[k]];
  return step;
}

}  // namespace

std::vector<Eigen::VectorXd> LinearizedJackknife(const Problem& problem, const Linearization& at,
                                                 const std::vector<int>& group_of_block,
                                                 double tolerance) {
  std::vector<Eigen::VectorXd> deviations;
  if (!at.valid) return deviations;
  int groups = 0;
  for (int g : group_of_block) groups = std::max(groups, g + 1);
  for (int g = 0; g < groups; ++g) {
    SparseJacobian J;
    Eigen::VectorXd r;
    WithoutGroup(problem, at, group_of_block, g, &J, &r);
    deviations.push_back(GaussNewtonStep(J, r, tolerance));
  }
  return deviations;
}

}  // namespace cellmetry
