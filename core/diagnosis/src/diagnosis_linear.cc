// The physics finder's linear algebra (diagnosis_linear.h): the model linearized at its estimate,
// projections out of its span, score tests, and greedy selection on bootstrap resamples of poses.
#include "diagnosis_linear.h"

#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/basics/statistics.h"
#include "cellmetry/model/robot_model.h"

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
    const int rows =
        (b + 1 < infos.size() ? first_row[b + 1] : static_cast<int>(J.rows())) - first_row[b];
    const MeasurementLabel* label = assembled->LabelOf(b);
    for (int k = 0; k < rows; ++k) {
      CandidateRow& row = out.rows[first_row[b] + k];
      row.kind = infos[b].kind;
      row.sigma = infos[b].sigma;
      if (label) row.label = *label;
      out.row_axis[first_row[b] + k] = k;
    }
  }
  return out;
}

namespace {

// Candidates evaluated together: as many as a pass's sparse Jacobian holds within
// kEntriesPerPass entries (12 bytes each: 200 MB), at least one pass of Jets. A cell's effect
// costs (EffectChainCost) carry Jets over every effect of their chain whichever are asked for,
// so each pass costs what the whole chain costs: many narrow passes would each redo all of
// them. An automatic-differentiation
// cost evaluates its chain once per kJetStride parameters asked for, in any grouping. Either
// way a column's entries are the same numbers in any pass.
constexpr Eigen::Index kEntriesPerPass = Eigen::Index(1) << 24;

int ColumnsPerPass(Eigen::Index rows) {
  const Eigen::Index fit = kEntriesPerPass / std::max<Eigen::Index>(rows, 1);
  return static_cast<int>(std::max<Eigen::Index>(kJetStride, fit));
}

// Groups of consecutive candidates (indices) whose free parameters fit one pass of
// `columns_per_pass`.
std::vector<std::vector<size_t>> PassGroups(const std::vector<int>& free_per_candidate,
                                            int columns_per_pass) {
  std::vector<std::vector<size_t>> groups;
  int filled = columns_per_pass;
  for (size_t k = 0; k < free_per_candidate.size(); ++k) {
    if (groups.empty() || filled + free_per_candidate[k] > columns_per_pass) {
      groups.emplace_back();
      filled = 0;
    }
    groups.back().push_back(k);
    filled += free_per_candidate[k];
  }
  return groups;
}

}  // namespace

std::vector<Eigen::MatrixXd> CandidateColumns(const WorkcellProblem& spec,
                                              const std::vector<WorkcellEffect>& candidates,
                                              const Recording& recording, const WorkcellData& data,
                                              const NoiseModel& noise,
                                              const WorkcellEstimate& estimate, Eigen::Index rows) {
  WorkcellProblem all = spec;
  all.effects.insert(all.effects.end(), candidates.begin(), candidates.end());
  auto assembled = AssembleWorkcell(all, recording, data, noise, estimate);
  const Problem& problem = assembled->problem;
  if (problem.num_residuals() < rows) {
    throw std::logic_error("CandidateColumns: fewer rows than the current model's");
  }
  const size_t first = spec.effects.size();  // the candidates' blocks follow the model's effects
  std::map<int, size_t> candidate_of_block;
  for (size_t k = 0; k < candidates.size(); ++k) {
    candidate_of_block[assembled->effect_block[first + k]] = k;
  }
  std::vector<int> free_per_candidate(candidates.size(), 0);
  for (const auto& p : problem.free_parameters()) {
    const auto k = candidate_of_block.find(p.block);
    if (k != candidate_of_block.end()) ++free_per_candidate[k->second];
  }
  std::vector<Eigen::MatrixXd> out(candidates.size());
  for (size_t k = 0; k < candidates.size(); ++k) {
    out[k] = Eigen::MatrixXd::Zero(rows, free_per_candidate[k]);
  }
  for (const auto& group :
       PassGroups(free_per_candidate, ColumnsPerPass(problem.num_residuals()))) {
    std::vector<int> blocks;
    for (size_t k : group) blocks.push_back(assembled->effect_block[first + k]);
    SparseJacobian J;
    std::vector<int> columns;  // free-parameter order: each candidate's own, in order
    if (!problem.EvaluateSparseColumns(blocks, &J, &columns)) {
      throw std::runtime_error("the candidates' Jacobian cannot be evaluated at the estimate");
    }
    std::vector<std::pair<size_t, int>> target(columns.size());  // candidate, its column
    std::vector<int> filled(candidates.size(), 0);
    for (size_t c = 0; c < columns.size(); ++c) {
      const size_t k = candidate_of_block.at(problem.free_parameters()[columns[c]].block);
      target[c] = {k, filled[k]++};
    }
    for (Eigen::Index row = 0; row < rows; ++row) {
      for (SparseJacobian::InnerIterator it(J, row); it; ++it) {
        out[target[it.col()].first](row, target[it.col()].second) = it.value();
      }
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

double CanonicalCorrelation(const Eigen::MatrixXd& U_a, const Eigen::MatrixXd& U_b) {
  const Eigen::MatrixXd overlap = U_a.transpose() * U_b;
  if (overlap.size() == 0) return 0.0;
  return Eigen::JacobiSVD<Eigen::MatrixXd>(overlap).singularValues()[0];
}

Eigen::VectorXd UnabsorbedSize(const Eigen::MatrixXd& P, const Eigen::VectorXd& r) {
  if (P.cols() == 0) return Eigen::VectorXd(0);
  return P.completeOrthogonalDecomposition().solve(r);
}

double RivalTestP(const Eigen::VectorXd& r, const Eigen::MatrixXd& U_chosen,
                  const Eigen::MatrixXd& U_rival, int draws, unsigned seed) {
  const int kc = static_cast<int>(U_chosen.cols()), kr = static_cast<int>(U_rival.cols());
  if (kc == 0) return 1.0;
  if (kr == 0) return 0.0;
  const Eigen::VectorXd a_rival = U_rival.transpose() * r;
  const double margin =
      Strength((U_chosen.transpose() * r).squaredNorm(), kc) - Strength(a_rival.squaredNorm(), kr);
  if (!(margin > 0)) return 1.0;
  const Eigen::MatrixXd C = U_chosen.transpose() * U_rival;
  Eigen::MatrixXd covariance(kc + kr, kc + kr);
  covariance << Eigen::MatrixXd::Identity(kc, kc), C, C.transpose(),
      Eigen::MatrixXd::Identity(kr, kr);
  Eigen::VectorXd mean(kc + kr);
  mean << C * a_rival, a_rival;
  const Eigen::MatrixXd draw_map = NormalDrawMap(covariance);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd n(kc + kr);
  int as_large = 0;
  for (int d = 0; d < draws; ++d) {
    for (Eigen::Index i = 0; i < n.size(); ++i) n[i] = normal(rng);
    const Eigen::VectorXd z = mean + draw_map * n;
    as_large +=
        Strength(z.head(kc).squaredNorm(), kc) - Strength(z.tail(kr).squaredNorm(), kr) >= margin;
  }
  return (as_large + 1.0) / (draws + 1.0);
}

double RivalTestPAt(double alpha, const Eigen::VectorXd& r, const Eigen::MatrixXd& U_chosen,
                    const Eigen::MatrixXd& U_rival, int draws, unsigned seed) {
  const double p = RivalTestP(r, U_chosen, U_rival, draws, seed);
  const double standard_error = std::sqrt(alpha * (1.0 - alpha) / draws);
  if (std::abs(p - alpha) >= 3.0 * standard_error) return p;
  constexpr int kMoreDraws = 20;
  return RivalTestP(r, U_chosen, U_rival, kMoreDraws * draws, seed ^ 0x9e3779b9u);
}

Eigen::MatrixXd UnabsorbedBasis(const Eigen::MatrixXd& J, const Eigen::MatrixXd& P) {
  const double total = J.norm();
  if (total == 0.0 || P.cols() == 0) return Eigen::MatrixXd(P.rows(), 0);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(P, Eigen::ComputeThinU);
  const auto& s = svd.singularValues();
  Eigen::Index k = 0;
  while (k < s.size() && s[k] > 1e-6 * total) ++k;  // sorted: the rest are smaller
  return svd.matrixU().leftCols(k);
}

double Strength(double statistic, int dof) { return -ChiSquareLogSurvival(statistic, dof); }

Eigen::MatrixXd NormalDrawMap(const Eigen::MatrixXd& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(covariance);
  return eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

double PlausibleNoncentrality(const Eigen::MatrixXd& P, const std::vector<Parameter>& parameters) {
  if (P.cols() == 0 || P.cols() != static_cast<Eigen::Index>(parameters.size())) return NAN;
  Eigen::VectorXd size(P.cols());
  for (Eigen::Index k = 0; k < P.cols(); ++k) {
    if (!parameters[static_cast<size_t>(k)].plausible) return NAN;
    size[k] = *parameters[static_cast<size_t>(k)].plausible;
  }
  const Eigen::MatrixXd scaled = P * size.asDiagonal();
  const Eigen::VectorXd s = Eigen::BDCSVD<Eigen::MatrixXd>(scaled).singularValues();
  return s.size() > 0 ? s[0] * s[0] : 0.0;
}

ScoreTest Score(const Eigen::VectorXd& r, const Eigen::MatrixXd& J_candidate,
                const Eigen::MatrixXd& P) {
  ScoreTest test;
  const double total = J_candidate.norm();
  if (total == 0.0) return test;
  test.unabsorbed = P.norm() / total;
  const Eigen::MatrixXd U = UnabsorbedBasis(J_candidate, P);
  test.statistic = (U.transpose() * r).squaredNorm();
  test.dof = static_cast<int>(U.cols());
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
      const double z = Strength(test.statistic, test.dof);
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

// Rows grouped by pose: the index (in order of first appearance) of each row's pose, -1 for
// rows of no pose (weight 1 in every resample).
struct PoseIndex {
  std::vector<int> of_row;
  int poses = 0;
};

PoseIndex IndexPoses(const std::vector<int>& row_pose) {
  PoseIndex out;
  std::map<int, int> index_of;
  for (int p : row_pose) {
    if (p >= 0 && !index_of.count(p)) index_of[p] = out.poses++;
    out.of_row.push_back(p >= 0 ? index_of.at(p) : -1);
  }
  return out;
}

// Each resample's count of every pose: poses drawn with replacement, in order from `seed`.
std::vector<std::vector<double>> DrawCounts(int poses, int resamples, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, poses - 1);
  std::vector<std::vector<double>> counts(resamples, std::vector<double>(poses, 0.0));
  for (auto& count : counts) {
    for (int i = 0; i < poses; ++i) count[pick(rng)] += 1.0;
  }
  return counts;
}

// One resample's selection on A's column blocks (J_model, each candidate, r), A any matrix whose
// cross products are the resample's.
std::vector<int> GreedyOnColumns(const Eigen::MatrixXd& A, Eigen::Index model_columns,
                                 const std::vector<Eigen::MatrixXd>& candidates,
                                 double penalty_per_dof, int max_steps) {
  std::vector<Eigen::MatrixXd> blocks;
  Eigen::Index at = model_columns;
  for (const auto& J : candidates) {
    blocks.push_back(A.middleCols(at, J.cols()));
    at += J.cols();
  }
  return GreedyInclusions(A.col(at), A.leftCols(model_columns), blocks, penalty_per_dof, max_steps);
}

Eigen::MatrixXd Stack(const Eigen::VectorXd& r, const Eigen::MatrixXd& J_model,
                      const std::vector<Eigen::MatrixXd>& candidates) {
  Eigen::Index n = J_model.cols() + 1;
  for (const auto& J : candidates) n += J.cols();
  Eigen::MatrixXd A(r.size(), n);
  A.leftCols(J_model.cols()) = J_model;
  Eigen::Index at = J_model.cols();
  for (const auto& J : candidates) {
    A.middleCols(at, J.cols()) = J;
    at += J.cols();
  }
  A.col(at) = r;
  return A;
}

// The cross products of A = [J_model, candidates, r] per pose, through A = Q R: per pose
// Q_p^T Q_p of its rows of Q, and the squared norms of its rows' part of each column of A
// (which columns a resample supports at all); `fixed`: the rows of no pose.
struct PoseCrossProducts {
  Eigen::MatrixXd R;
  std::vector<Eigen::MatrixXd> QtQ;
  std::vector<Eigen::VectorXd> support;
  Eigen::MatrixXd fixed_QtQ;
  Eigen::VectorXd fixed_support;
};

PoseCrossProducts CrossProducts(Eigen::MatrixXd A, const PoseIndex& index) {
  std::vector<std::vector<Eigen::Index>> rows(index.poses + 1);  // last: rows of no pose
  for (size_t i = 0; i < index.of_row.size(); ++i) {
    rows[index.of_row[i] >= 0 ? index.of_row[i] : index.poses].push_back(i);
  }
  std::vector<Eigen::VectorXd> support(rows.size());
  for (size_t p = 0; p < rows.size(); ++p) {
    support[p] = A(rows[p], Eigen::all).colwise().squaredNorm().transpose();
  }
  const Eigen::Index n = A.cols();
  const Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(A);  // in place: A holds Q and R
  PoseCrossProducts out;
  out.R = qr.matrixQR().topRows(n).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(A.rows(), n);
  std::vector<Eigen::MatrixXd> QtQ(rows.size());
  tbb::parallel_for(size_t(0), rows.size(), [&](size_t p) {
    const Eigen::MatrixXd Q_p = Q(rows[p], Eigen::all);
    QtQ[p] = Q_p.transpose() * Q_p;
  });
  out.fixed_QtQ = std::move(QtQ.back());
  out.fixed_support = std::move(support.back());
  QtQ.pop_back();
  support.pop_back();
  out.QtQ = std::move(QtQ);
  out.support = std::move(support);
  return out;
}

// B (N x N) with B^T B = R^T M R for M = F^T F positive semidefinite (pivoted LDL^T); columns
// without `support` are zero, as they are in the reweighted rows.
Eigen::MatrixXd CompressedRows(const Eigen::MatrixXd& M, const Eigen::MatrixXd& R,
                               const Eigen::VectorXd& support) {
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(M);
  Eigen::MatrixXd B = ldlt.transpositionsP() * R;
  B = ldlt.matrixU() * B;
  B = ldlt.vectorD().cwiseMax(0.0).cwiseSqrt().asDiagonal() * B;
  for (Eigen::Index j = 0; j < B.cols(); ++j) {
    if (support[j] == 0.0) B.col(j).setZero();
  }
  return B;
}

}  // namespace

std::vector<std::vector<int>> BootstrapInclusions(const Eigen::VectorXd& r,
                                                  const Eigen::MatrixXd& J_model,
                                                  const std::vector<Eigen::MatrixXd>& candidates,
                                                  const std::vector<int>& row_pose, int resamples,
                                                  double penalty_per_dof, int max_steps,
                                                  unsigned seed) {
  const PoseIndex index = IndexPoses(row_pose);
  if (index.poses == 0 || candidates.empty()) return {};
  Eigen::MatrixXd A = Stack(r, J_model, candidates);
  if (A.rows() <= A.cols()) {
    return BootstrapInclusionsOnRows(r, J_model, candidates, row_pose, resamples, penalty_per_dof,
                                     max_steps, seed);
  }
  const std::vector<std::vector<double>> counts = DrawCounts(index.poses, resamples, seed);
  const PoseCrossProducts pose = CrossProducts(std::move(A), index);
  std::vector<std::vector<int>> out(resamples);
  tbb::parallel_for(0, resamples, [&](int b) {
    Eigen::MatrixXd M = pose.fixed_QtQ;
    Eigen::VectorXd support = pose.fixed_support;
    for (int p = 0; p < index.poses; ++p) {
      if (counts[b][p] == 0.0) continue;
      M += counts[b][p] * pose.QtQ[p];
      support += counts[b][p] * pose.support[p];
    }
    out[b] = GreedyOnColumns(CompressedRows(M, pose.R, support), J_model.cols(), candidates,
                             penalty_per_dof, max_steps);
  });
  return out;
}

std::vector<std::vector<int>> BootstrapInclusionsOnRows(
    const Eigen::VectorXd& r, const Eigen::MatrixXd& J_model,
    const std::vector<Eigen::MatrixXd>& candidates, const std::vector<int>& row_pose, int resamples,
    double penalty_per_dof, int max_steps, unsigned seed) {
  const PoseIndex index = IndexPoses(row_pose);
  if (index.poses == 0 || candidates.empty()) return {};
  const std::vector<std::vector<double>> counts = DrawCounts(index.poses, resamples, seed);
  const Eigen::MatrixXd A = Stack(r, J_model, candidates);
  std::vector<std::vector<int>> out(resamples);
  tbb::parallel_for(0, resamples, [&](int b) {
    // Rows weighted by how often their pose was drawn; sqrt(w) scales whitened rows.
    Eigen::VectorXd sqrt_w(A.rows());
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      const int p = index.of_row[i];
      sqrt_w[i] = p < 0 ? 1.0 : std::sqrt(counts[b][p]);
    }
    out[b] = GreedyOnColumns(sqrt_w.asDiagonal() * A, J_model.cols(), candidates, penalty_per_dof,
                             max_steps);
  });
  return out;
}

}  // namespace cellmetry
