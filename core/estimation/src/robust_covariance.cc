// The cluster-robust covariance and the jackknife spread (robust_covariance.h).
#include "cellmetry/estimation/robust_covariance.h"

#include <cmath>
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

}  // namespace cellmetry
