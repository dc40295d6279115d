// The physics finder's linear algebra (diagnosis_linear.h): the model linearized at its estimate,
// projections out of its span, score tests, and greedy selection on bootstrap resamples of poses.
#include "diagnosis_linear.h"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <map>

#include "cellmetry/basics/statistics.h"

namespace cellmetry {

CandidateLinearization LinearizeWithCandidate(const WorkcellProblem& spec,
                                              const Recording& recording, const WorkcellData& data,
                                              const NoiseModel& noise,
                                              const WorkcellEstimate& estimate, bool candidate) {
  auto assembled = AssembleWorkcell(spec, recording, data, noise, estimate);
  Problem& problem = assembled->problem;
  CandidateLinearization out;
  Eigen::MatrixXd J;
  problem.Evaluate(nullptr, &out.r, &J, false);
  const int candidate_block = candidate ? assembled->effect_block.back() : -1;
  std::vector<int> model_columns, candidate_columns;
  const auto& free = problem.free_parameters();
  for (int c = 0; c < static_cast<int>(free.size()); ++c) {
    (free[c].block == candidate_block ? candidate_columns : model_columns).push_back(c);
  }
  out.J_model.resize(J.rows(), model_columns.size());
  for (size_t i = 0; i < model_columns.size(); ++i) out.J_model.col(i) = J.col(model_columns[i]);
  out.J_candidate.resize(J.rows(), candidate_columns.size());
  for (size_t i = 0; i < candidate_columns.size(); ++i) {
    out.J_candidate.col(i) = J.col(candidate_columns[i]);
  }
  const auto& infos = problem.residual_infos();
  const auto& first_row = problem.residual_rows();
  out.rows.resize(J.rows());
  out.row_axis.assign(J.rows(), 0);
  for (size_t b = 0; b < infos.size(); ++b) {
    const int rows = (b + 1 < infos.size() ? first_row[b + 1] : static_cast<int>(J.rows())) -
                     first_row[b];
    for (int k = 0; k < rows; ++k) {
      out.rows[first_row[b] + k] = infos[b];
      out.row_axis[first_row[b] + k] = k;
    }
  }
  return out;
}

Eigen::MatrixXd OrthonormalBasis(const Eigen::MatrixXd& columns) {
  if (columns.cols() == 0) return Eigen::MatrixXd(columns.rows(), 0);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(columns);
  qr.setThreshold(1e-10);
  const Eigen::Index rank = qr.rank();
  Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(columns.rows(), rank);
  return Q;
}

Eigen::MatrixXd ProjectOut(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& X) {
  if (Q.cols() == 0) return X;
  return X - Q * (Q.transpose() * X);
}

ScoreTest Score(const Eigen::VectorXd& r, const Eigen::MatrixXd& J_candidate,
                const Eigen::MatrixXd& P) {
  ScoreTest test;
  const double total = J_candidate.norm();
  if (total == 0.0) return test;
  test.unabsorbed = P.norm() / total;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(P, Eigen::ComputeThinU);
  const auto& s = svd.singularValues();
  // Directions of P too small to carry information (1e-6 of the candidate's own scale).
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (s[i] <= 1e-6 * total) continue;
    const double projection = svd.matrixU().col(i).dot(r);
    test.statistic += projection * projection;
    ++test.dof;
  }
  test.p_value = test.dof > 0 ? ChiSquareSurvival(test.statistic, test.dof) : 1.0;
  return test;
}

namespace {

// One resample's greedy selection (BootstrapInclusions) on whitened, reweighted rows.
std::vector<int> GreedyInclusions(const Eigen::VectorXd& r, const Eigen::MatrixXd& J_model,
                                  const std::vector<Eigen::MatrixXd>& candidates,
                                  double penalty_per_dof, int max_steps) {
  std::vector<int> included;
  std::vector<bool> taken(candidates.size(), false);
  Eigen::MatrixXd model = J_model;
  for (int step = 0; step < max_steps; ++step) {
    const Eigen::MatrixXd Q = OrthonormalBasis(model);
    const Eigen::VectorXd r_refit = ProjectOut(Q, r);  // the model refitted on the resample
    double best_z = -INFINITY, best_gain = 0.0;
    int best = -1;
    for (size_t c = 0; c < candidates.size(); ++c) {
      if (taken[c]) continue;
      const ScoreTest test = Score(r_refit, candidates[c], ProjectOut(Q, candidates[c]));
      if (test.dof == 0) continue;
      const double z = -ChiSquareLogSurvival(test.statistic, test.dof);
      if (z > best_z) {
        best_z = z, best = static_cast<int>(c);
        best_gain = test.statistic - test.dof * penalty_per_dof;
      }
    }
    if (best < 0 || best_gain <= 0.0) break;  // BIC would not fall
    included.push_back(best);
    taken[best] = true;
    Eigen::MatrixXd grown(model.rows(), model.cols() + candidates[best].cols());
    grown << model, candidates[best];
    model = std::move(grown);
  }
  return included;
}

}  // namespace

std::vector<std::vector<int>> BootstrapInclusions(const Eigen::VectorXd& r,
                                                  const Eigen::MatrixXd& J_model,
                                                  const std::vector<Eigen::MatrixXd>& candidates,
                                                  const std::vector<int>& row_pose, int resamples,
                                                  double penalty_per_dof, int max_steps,
                                                  unsigned seed) {
  std::vector<int> poses;
  std::map<int, int> index_of;
  for (int p : row_pose) {
    if (p >= 0 && !index_of.count(p)) {
      index_of[p] = static_cast<int>(poses.size());
      poses.push_back(p);
    }
  }
  std::vector<std::vector<int>> out;
  if (poses.empty() || candidates.empty()) return out;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(poses.size()) - 1);
  for (int b = 0; b < resamples; ++b) {
    std::vector<double> count(poses.size(), 0.0);
    for (size_t i = 0; i < poses.size(); ++i) count[pick(rng)] += 1.0;
    // Rows weighted by how often their pose was drawn; sqrt(w) scales whitened rows.
    Eigen::VectorXd sqrt_w(r.size());
    for (Eigen::Index i = 0; i < r.size(); ++i) {
      sqrt_w[i] = row_pose[i] < 0 ? 1.0 : std::sqrt(count[index_of.at(row_pose[i])]);
    }
    std::vector<Eigen::MatrixXd> weighted;
    for (const auto& J : candidates) weighted.push_back(sqrt_w.asDiagonal() * J);
    out.push_back(GreedyInclusions(sqrt_w.asDiagonal() * r, sqrt_w.asDiagonal() * J_model,
                                   weighted, penalty_per_dof, max_steps));
  }
  return out;
}

}  // namespace cellmetry
