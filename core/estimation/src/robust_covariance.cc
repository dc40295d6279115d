// The cluster-robust covariance and the jackknife spread (robust_covariance.h).
#include "cellmetry/estimation/robust_covariance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include <Eigen/SparseCore>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/basics/statistics.h"

namespace cellmetry {

namespace {

// One cluster's score J_g^T r_g on the columns it touches.
struct ClusterScore {
  std::vector<int> columns;
  std::vector<double> values;
};

// The scores of the clusters of `cluster_of_block`, ordered by cluster id (blocks with a
// negative id, priors, each a cluster of their own, after the others). `ordered`: how many lead
// the list (the clusters with an id, in its order).
std::vector<ClusterScore> ClusterScores(const Problem& problem, const Linearization& at,
                                        const std::vector<int>& cluster_of_block, int* ordered) {
  const int n = problem.num_free();
  const Eigen::VectorXd& r = at.residuals;
  const SparseJacobian& J = at.jacobian;
  const auto& rows = problem.residual_rows();
  std::map<int, std::vector<int>> by_id;  // the blocks of each cluster with an id, in id order
  std::vector<int> own;                   // blocks that are clusters of their own
  for (size_t b = 0; b < rows.size(); ++b) {
    if (b < cluster_of_block.size() && cluster_of_block[b] >= 0) {
      by_id[cluster_of_block[b]].push_back(static_cast<int>(b));
    } else {
      own.push_back(static_cast<int>(b));
    }
  }
  std::vector<std::vector<int>> members;
  for (auto& [id, blocks] : by_id) members.push_back(std::move(blocks));
  *ordered = static_cast<int>(members.size());
  for (int b : own) members.push_back({b});
  // Each score summed densely over the columns it touches and kept on those only: a pose
  // touches one robot's and a few cameras' columns, so the meat costs the sum of each score's
  // nonzeros squared, where dense scores would cost clusters x parameters^2 (and as much
  // memory: 300 MB for a 2.5 million observation cell).
  std::vector<ClusterScore> scores;
  scores.reserve(members.size());
  Eigen::VectorXd score = Eigen::VectorXd::Zero(n);
  std::vector<char> touched(static_cast<size_t>(n), 0);
  for (const std::vector<int>& blocks : members) {
    ClusterScore out;
    for (int b : blocks) {
      const int end =
          b + 1 < static_cast<int>(rows.size()) ? rows[b + 1] : static_cast<int>(r.size());
      for (int row = rows[b]; row < end; ++row) {
        for (SparseJacobian::InnerIterator e(J, row); e; ++e) {
          const int c = static_cast<int>(e.col());
          if (!touched[c]) {
            touched[c] = 1;
            out.columns.push_back(c);
          }
          score[c] += e.value() * r[row];
        }
      }
    }
    for (int c : out.columns) {
      out.values.push_back(score[c]);
      score[c] = 0.0;
      touched[c] = 0;
    }
    scores.push_back(std::move(out));
  }
  return scores;
}

// meat += weight * (a b^T + b a^T), or weight * a a^T where `a` and `b` are the same score.
void AddOuter(const ClusterScore& a, const ClusterScore& b, double weight, Eigen::MatrixXd* meat) {
  const bool same = &a == &b;
  for (size_t i = 0; i < a.columns.size(); ++i) {
    for (size_t k = 0; k < b.columns.size(); ++k) {
      const double v = weight * a.values[i] * b.values[k];
      (*meat)(a.columns[i], b.columns[k]) += v;
      if (!same) (*meat)(b.columns[k], a.columns[i]) += v;
    }
  }
}

// One column of the ordered scores as a series, zero where a cluster does not touch it.
Eigen::VectorXd ScoreSeries(const std::vector<ClusterScore>& scores, int ordered, int column) {
  Eigen::VectorXd series = Eigen::VectorXd::Zero(ordered);
  for (int g = 0; g < ordered; ++g) {
    const auto& s = scores[static_cast<size_t>(g)];
    for (size_t i = 0; i < s.columns.size(); ++i) {
      if (s.columns[i] == column) series[g] = s.values[i];
    }
  }
  return series;
}

}  // namespace

int BartlettBandwidth(const std::vector<Eigen::VectorXd>& series) {
  double numerator = 0.0, denominator = 0.0;
  Eigen::Index T = 0;
  for (const Eigen::VectorXd& x : series) {
    T = std::max(T, x.size());
    if (x.size() < 3) continue;
    const Eigen::VectorXd lead = x.tail(x.size() - 1), lag = x.head(x.size() - 1);
    const double ss = lag.squaredNorm();
    if (ss <= 0.0) continue;
    // An AR(1) fitted by least squares; rho is kept below 0.97, as Andrews advises, so that one
    // near-unit-root series does not decide the bandwidth alone.
    const double rho = std::clamp(lead.dot(lag) / ss, -0.97, 0.97);
    const double innovation = (lead - rho * lag).squaredNorm() / static_cast<double>(lag.size());
    const double s4 = innovation * innovation;
    numerator += 4.0 * rho * rho * s4 / (std::pow(1.0 - rho, 6) * std::pow(1.0 + rho, 2));
    denominator += s4 / std::pow(1.0 - rho, 4);
  }
  if (denominator <= 0.0 || T < 3) return 0;
  const double alpha = numerator / denominator;
  const double bandwidth = 1.1447 * std::cbrt(alpha * static_cast<double>(T));
  return std::min(static_cast<int>(bandwidth), static_cast<int>(T) / 4);
}

Eigen::MatrixXd ClusterRobustCovariance(const Problem& problem, const Linearization& at,
                                        const std::vector<int>& cluster_of_block,
                                        const Uncertainty& model) {
  return SerialClusterRobustCovariance(problem, at, cluster_of_block, model, /*serial=*/false)
      .covariance;
}

ClusterRobust SerialClusterRobustCovariance(const Problem& problem, const Linearization& at,
                                            const std::vector<int>& cluster_of_block,
                                            const Uncertainty& model, bool serial) {
  ClusterRobust out;
  const int n = problem.num_free();
  if (n == 0 || !at.valid) return out;
  int ordered = 0;
  const std::vector<ClusterScore> scores = ClusterScores(problem, at, cluster_of_block, &ordered);
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(n, n);
  for (const ClusterScore& s : scores) AddOuter(s, s, 1.0, &meat);
  if (serial && ordered >= 3) {
    // Each column's series standardized, so that mm and rad weigh alike in the bandwidth.
    std::vector<Eigen::VectorXd> series;
    for (int c = 0; c < n; ++c) {
      Eigen::VectorXd x = ScoreSeries(scores, ordered, c);
      const double norm = x.norm();
      if (norm > 0.0) series.push_back(x / norm);
    }
    out.lag = BartlettBandwidth(series);
    for (int lag = 1; lag <= out.lag; ++lag) {
      const double weight = 1.0 - lag / (out.lag + 1.0);
      for (int g = 0; g + lag < ordered; ++g) {
        AddOuter(scores[static_cast<size_t>(g)], scores[static_cast<size_t>(g + lag)], weight,
                 &meat);
      }
    }
  }
  const double G = static_cast<double>(scores.size());
  const Eigen::MatrixXd& bread = model.inverse_information;  // (J^T J)^-1
  out.covariance = bread * meat * bread * (G > 1 ? G / (G - 1) : 1.0);
  return out;
}

void CombineUncertainty(const Eigen::MatrixXd& cluster, const Jackknife& jackknife, Uncertainty* u,
                        double quantile) {
  const Eigen::Index n = u->sigma.size();
  u->sigma_model = u->sigma;
  u->sigma_cluster = cluster.size() == n * n
                         ? Eigen::VectorXd(cluster.diagonal().cwiseMax(0.0).cwiseSqrt())
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

// What one group of rows (or the rows in no group) contributes: its R factor, J^T r and the
// squared column norms. A leave-one-out estimate is the sum over the other groups.
struct GroupPart {
  Eigen::MatrixXd R;
  Eigen::VectorXd gradient;       // J_g^T r_g
  Eigen::VectorXd squared_norms;  // per column
};

// `rows` of J (or of its Gram rows) as a matrix of their own.
SparseJacobian SubRows(const SparseJacobian& J, const std::vector<int>& rows) {
  Eigen::Index nonzeros = 0;
  for (int row : rows) nonzeros += J.innerVector(row).nonZeros();
  SparseJacobian out(static_cast<Eigen::Index>(rows.size()), J.cols());
  out.resizeNonZeros(nonzeros);
  Eigen::Index at_entry = 0;
  for (size_t k = 0; k < rows.size(); ++k) {
    out.outerIndexPtr()[k] = static_cast<int>(at_entry);
    for (SparseJacobian::InnerIterator it(J, rows[k]); it; ++it, ++at_entry) {
      out.innerIndexPtr()[at_entry] = static_cast<int>(it.col());
      out.valuePtr()[at_entry] = it.value();
    }
  }
  out.outerIndexPtr()[rows.size()] = static_cast<int>(at_entry);
  return out;
}

// Parts of group 0 .. groups - 1, and last the rows in no group: J^T r and the column norms
// from J's rows, the R factors from the Gram rows (gram_rows.h) where every block of a unit is
// in one group (a camera's: a unit is one camera's), else from J's rows.
std::vector<GroupPart> GroupParts(const Problem& problem, const Linearization& at,
                                  const std::vector<int>& group_of_block, int groups) {
  const auto& rows = problem.residual_rows();
  const int num_rows = static_cast<int>(at.residuals.size());
  auto group_of = [&](size_t b) {
    return b < group_of_block.size() && group_of_block[b] >= 0 ? group_of_block[b] : groups;
  };
  const Eigen::Index n = at.jacobian.cols();
  std::vector<GroupPart> parts(static_cast<size_t>(groups) + 1,
                               GroupPart{{}, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)});
  std::vector<std::vector<int>> members(static_cast<size_t>(groups) + 1);
  for (size_t b = 0; b < rows.size(); ++b) {
    GroupPart& part = parts[static_cast<size_t>(group_of(b))];
    const int end = b + 1 < rows.size() ? rows[b + 1] : num_rows;
    for (int row = rows[b]; row < end; ++row) {
      members[static_cast<size_t>(group_of(b))].push_back(row);
      for (SparseJacobian::InnerIterator it(at.jacobian, row); it; ++it) {
        part.gradient[it.col()] += it.value() * at.residuals[row];
        part.squared_norms[it.col()] += it.value() * it.value();
      }
    }
  }
  const GramRows& gram = at.gram;
  bool by_gram = gram.rows.rows() > 0 && gram.row_of_block.size() == rows.size();
  for (size_t b = 0; by_gram && b < rows.size(); ++b) {
    const int row = gram.row_of_block[b];
    by_gram = row >= 0 && group_of(static_cast<size_t>(gram.block[row])) == group_of(b);
  }
  if (by_gram) {
    for (auto& m : members) m.clear();
    for (size_t row = 0; row < gram.block.size(); ++row) {
      members[static_cast<size_t>(group_of(static_cast<size_t>(gram.block[row])))].push_back(
          static_cast<int>(row));
    }
  }
  const SparseJacobian& source = by_gram ? gram.rows : at.jacobian;
  for (size_t g = 0; g < parts.size(); ++g) parts[g].R = RFactor(SubRows(source, members[g]));
  return parts;
}

// argmin_d |J d + r|^2 over the columns J determines at `tolerance`, NaN elsewhere, from J's R
// factor, column norms and J^T r; solved on the column-scaled R's SVD, like the covariance.
Eigen::VectorXd GaussNewtonStep(const Eigen::MatrixXd& R, const Eigen::VectorXd& norms,
                                const Eigen::VectorXd& gradient, double tolerance) {
  const Eigen::Index n = R.cols();
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
  Eigen::VectorXd scaled_gradient(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    scaled.col(k) = R.col(columns[k]) / norms[columns[k]];
    scaled_gradient[k] = gradient[columns[k]] / norms[columns[k]];
  }
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  Eigen::VectorXd inv_s2 = Eigen::VectorXd::Zero(s.size());
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (s[i] > 1e-14 * s[0]) inv_s2[i] = 1.0 / (s[i] * s[i]);
  }
  const Eigen::MatrixXd& V = svd.matrixV();
  const Eigen::VectorXd scaled_step =
      -(V * (inv_s2.asDiagonal() * (V.transpose() * scaled_gradient)));
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
  const std::vector<GroupPart> parts = GroupParts(problem, at, group_of_block, groups);
  const Eigen::Index n = at.jacobian.cols();
  for (int left_out = 0; left_out < groups; ++left_out) {
    // The other groups' R factors stacked and reduced: R^T R = J_{-g}^T J_{-g}.
    Eigen::MatrixXd stack(static_cast<Eigen::Index>(parts.size() - 1) * n, n);
    Eigen::VectorXd gradient = Eigen::VectorXd::Zero(n), squared_norms = Eigen::VectorXd::Zero(n);
    Eigen::Index at_row = 0;
    for (size_t g = 0; g < parts.size(); ++g) {
      if (static_cast<int>(g) == left_out) continue;
      stack.middleRows(at_row, n) = parts[g].R;
      at_row += n;
      gradient += parts[g].gradient;
      squared_norms += parts[g].squared_norms;
    }
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(stack);
    const Eigen::MatrixXd R = qr.matrixQR().topRows(n).triangularView<Eigen::Upper>();
    deviations.push_back(GaussNewtonStep(R, squared_norms.cwiseSqrt(), gradient, tolerance));
  }
  return deviations;
}

}  // namespace cellmetry
