// The sparse path to identifiability and sigma: the grouped R factor, the sparse
// evaluation, and the answers built on them, against the dense computation they replaced.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <map>
#include <random>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_initial.h"
#include "cellmetry/estimation/estimation_quality.h"
#include "cellmetry/estimation/noise_model.h"
#include "cellmetry/estimation/r_factor.h"
#include "cellmetry/estimation/robust_covariance.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using testing::JobSolver;
using testing::Plugins;
using testing::Source;

// A cell-like Jacobian: groups of rows that each touch a few of `n` columns, plus some rows
// with a pattern of their own.
SparseJacobian CellLikeJacobian(int n, int rows, std::mt19937& rng) {
  std::uniform_int_distribution<int> column(0, n - 1);
  std::normal_distribution<double> value(0.0, 1.0);
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<std::vector<int>> patterns(12);
  for (auto& pattern : patterns) {
    for (int k = 0; k < 5; ++k) pattern.push_back(column(rng));
  }
  for (int row = 0; row < rows; ++row) {
    const auto& pattern = patterns[row % 13 == 0 ? 0 : row % patterns.size()];
    std::vector<int> columns = pattern;
    if (row % 13 == 0) columns.push_back(column(rng));  // its own pattern
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    for (int c : columns) entries.emplace_back(row, c, value(rng) * (c % 3 == 0 ? 1e3 : 1.0));
  }
  SparseJacobian J(rows, n);
  J.setFromTriplets(entries.begin(), entries.end());
  return J;
}

TEST(RFactor, HasTheGramMatrixAndSingularValuesOfTheDenseJacobian) {
  std::mt19937 rng(3);
  for (int rows : {7, 40, 900}) {  // fewer rows than columns, a few more, many more
    const SparseJacobian J = CellLikeJacobian(20, rows, rng);
    const Eigen::MatrixXd dense(J);
    const Eigen::MatrixXd R = RFactor(J);
    ASSERT_EQ(R.rows(), 20);
    const Eigen::MatrixXd gram = dense.transpose() * dense;
    EXPECT_LT((R.transpose() * R - gram).norm(), 1e-12 * gram.norm()) << rows << " rows";
    const Eigen::VectorXd s_dense = Eigen::JacobiSVD<Eigen::MatrixXd>(dense).singularValues();
    const Eigen::VectorXd s_R = Eigen::JacobiSVD<Eigen::MatrixXd>(R).singularValues();
    for (Eigen::Index i = 0; i < s_dense.size(); ++i) {
      EXPECT_NEAR(s_R[i], s_dense[i], 1e-10 * s_dense[0]) << rows << " rows, singular value " << i;
    }
  }
}

TEST(RFactor, KeepsATinySingularValueTiny) {
  // Column 3 = column 1 + 1e-9 * noise: unidentifiable at any sensible tolerance. The normal
  // equations would lose it (1e-18 relative is below double precision); the R factor keeps it.
  std::mt19937 rng(5);
  SparseJacobian J = CellLikeJacobian(6, 300, rng);
  Eigen::MatrixXd dense(J);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (Eigen::Index row = 0; row < dense.rows(); ++row) {
    dense(row, 3) = dense(row, 1) + 1e-9 * noise(rng);
  }
  J = dense.sparseView();
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(RFactor(J)).singularValues();
  const Eigen::VectorXd s_dense = Eigen::JacobiSVD<Eigen::MatrixXd>(dense).singularValues();
  EXPECT_LT(s[5], 1e-6 * s[0]);
  EXPECT_NEAR(s[5], s_dense[5], 1e-3 * s_dense[5]);
}

// The dense computation the sparse path replaced: SVD of the column-scaled dense Jacobian.
// Where the problem has priors, the measurements' information alone is divided by the scale:
// (J^T J - P) / scale + P, P the priors' 1 / sigma^2, so a prior keeps its stated sigma.
Eigen::VectorXd DenseSigma(Problem& problem, double scale) {
  Eigen::MatrixXd J;
  EXPECT_TRUE(problem.Evaluate(nullptr, nullptr, &J, false));
  Eigen::VectorXd prior = Eigen::VectorXd::Zero(J.cols());
  const auto& free = problem.free_parameters();
  for (size_t i = 0; i < free.size(); ++i) {
    const Parameter& p = problem.block_parameters(free[i].block)[free[i].index];
    if (!p.prior_sigma) continue;
    prior[static_cast<Eigen::Index>(i)] = 1.0 / (*p.prior_sigma * *p.prior_sigma);
  }
  Eigen::VectorXd norms(J.cols());
  for (Eigen::Index j = 0; j < J.cols(); ++j) norms[j] = J.col(j).norm();
  const Eigen::MatrixXd scaled = J * norms.cwiseInverse().asDiagonal();
  Eigen::MatrixXd information = scaled.transpose() * scaled;
  const Eigen::VectorXd scaled_prior = prior.cwiseProduct(norms.cwiseInverse().cwiseAbs2());
  information.diagonal() -= scaled_prior;
  information /= scale;
  information.diagonal() += scaled_prior;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(information, Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  Eigen::VectorXd inv_s = Eigen::VectorXd::Zero(s.size());
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (s[i] > 1e-28 * s[0]) inv_s[i] = 1.0 / s[i];
  }
  const Eigen::MatrixXd& V = svd.matrixV();
  const Eigen::VectorXd scaled_variance = (V * inv_s.asDiagonal() * V.transpose()).diagonal();
  return scaled_variance.cwiseSqrt().cwiseQuotient(norms);
}

// A job's problem assembled at its closed-form start and solved.
struct Solved {
  WorkcellJob job;
  Recording recording;
  std::unique_ptr<WorkcellData> data;  // the residuals point into it: kept, at a fixed address
  std::unique_ptr<AssembledWorkcell> assembled;
};
Solved Solve(const std::string& job_file) {
  Solved out;
  out.job = LoadWorkcellJob(Source(job_file), Plugins());
  out.recording = ReadRecording(out.job.recording);
  const WorkcellProblem& spec = out.job.problem;
  out.data = std::make_unique<WorkcellData>(PrepareWorkcellData(spec, out.recording));
  const NoiseModel noise = BuildNoiseModel(out.recording, spec.noise);
  out.assembled = AssembleWorkcell(spec, out.recording, *out.data, noise,
                                   InitialEstimate(spec, out.recording, *out.data));
  JobSolver(out.job)()->Solve(out.assembled->problem);
  return out;
}

TEST(SparsePath, EvaluatesTheSameJacobianAsCeres) {
  Solved solved = Solve("configs/jobs/vsb_exp_a.yaml");
  Problem& problem = solved.assembled->problem;
  Eigen::MatrixXd dense;
  Eigen::VectorXd r_dense, r_sparse;
  SparseJacobian sparse;
  ASSERT_TRUE(problem.Evaluate(nullptr, &r_dense, &dense, false));
  ASSERT_TRUE(problem.EvaluateSparse(&r_sparse, &sparse));
  // The job's effect costs share their predictions (effect_chain_cost.h): the sparse path
  // compares each capture with its pose's measured prediction (Compare, D A), Ceres evaluates
  // each block through its own Jets; the same numbers but for rounding.
  // The ten captures of a pose share theirs: 22,500 blocks in about 2,250 predictions.
  EXPECT_LT(problem.num_predictions(), problem.residual_rows().size() / 8);
  EXPECT_LT((r_sparse - r_dense).cwiseAbs().maxCoeff(), 1e-13 * r_dense.cwiseAbs().maxCoeff());
  EXPECT_LT((Eigen::MatrixXd(sparse) - dense).cwiseAbs().maxCoeff(),
            1e-14 * dense.cwiseAbs().maxCoeff());
}

// The Gram rows (gram_rows.h) have J's Gram matrix, hence its R factor up to row signs and its
// column norms, on a tenth of its rows where the captures of a pose share a prediction; both
// the effect costs (vsb_exp_a) and the plain chain (the geometry job) share.
TEST(SparsePath, GramRowsHaveTheJacobiansGramMatrix) {
  for (const char* job : {"configs/jobs/vsb_exp_a.yaml", "configs/jobs/vsb_exp_a_geometry.yaml"}) {
    Solved solved = Solve(job);
    const Linearization at = Linearize(solved.assembled->problem);
    ASSERT_TRUE(at.valid);
    EXPECT_LT(at.gram.rows.rows(), at.jacobian.rows() / 8) << job;
    const Eigen::MatrixXd J(at.jacobian);
    const Eigen::MatrixXd G = J.transpose() * J;
    const Eigen::MatrixXd gram(at.gram.rows);
    EXPECT_LT((gram.transpose() * gram - G).norm(), 1e-12 * G.norm()) << job;
    const Eigen::MatrixXd R = RFactor(at.gram.rows), R_full = RFactor(at.jacobian);
    EXPECT_LT((R.transpose() * R - R_full.transpose() * R_full).norm(), 1e-12 * G.norm()) << job;
    EXPECT_LT((ColumnNorms(at.gram.rows) - ColumnNorms(at.jacobian)).norm(),
              1e-12 * ColumnNorms(at.jacobian).norm())
        << job;
    for (size_t b = 0; b < at.gram.row_of_block.size(); ++b) {
      const int row = at.gram.row_of_block[b];
      ASSERT_GE(row, 0);
      const MeasurementLabel* label = solved.assembled->LabelOf(b);
      const MeasurementLabel* stands_for = solved.assembled->LabelOf(at.gram.block[row]);
      ASSERT_EQ(label == nullptr, stands_for == nullptr);
      if (label) {
        EXPECT_EQ(label->camera, stands_for->camera);
      }
    }
    // Asked alone (J never stored, as the identifiability check before a solve asks), the
    // same rows to the bit.
    ASSERT_TRUE(solved.assembled->problem.HasGramRows()) << job;
    GramRows alone;
    ASSERT_TRUE(solved.assembled->problem.EvaluateSparse(nullptr, nullptr, &alone)) << job;
    EXPECT_EQ((Eigen::MatrixXd(alone.rows) - gram).cwiseAbs().maxCoeff(), 0.0) << job;
    EXPECT_EQ(alone.block, at.gram.block) << job;
    EXPECT_EQ(alone.row_of_block, at.gram.row_of_block) << job;
  }
}

// Handing a linearization on moves its Jacobian and Gram rows (Eigen's SparseMatrix alone would
// copy them): the same storage, the same entries.
TEST(SparsePath, LinearizationMovesWithoutCopyingItsJacobian) {
  Solved solved = Solve("configs/jobs/vsb_exp_a_geometry.yaml");
  Linearization at = Linearize(solved.assembled->problem);
  ASSERT_GT(at.gram.rows.rows(), 0);
  const double* entries = at.jacobian.valuePtr();
  const double* gram_entries = at.gram.rows.valuePtr();
  const Eigen::MatrixXd J(at.jacobian);
  Linearization moved = std::move(at);
  EXPECT_EQ(moved.jacobian.valuePtr(), entries);
  EXPECT_EQ(moved.gram.rows.valuePtr(), gram_entries);
  Linearization assigned;
  assigned = std::move(moved);
  EXPECT_EQ(assigned.jacobian.valuePtr(), entries);
  EXPECT_TRUE(assigned.valid);
  EXPECT_EQ((Eigen::MatrixXd(assigned.jacobian) - J).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SparsePath, SigmaAndVerdictsAreTheDensePathsOnTheBundledJobs) {
  for (const char* job : {"configs/jobs/vsb_sim_b.yaml", "configs/jobs/vsb_exp_a_geometry.yaml",
                          "configs/jobs/vsb_exp_a.yaml"}) {
    Solved solved = Solve(job);
    Problem& problem = solved.assembled->problem;
    const Uncertainty u = ComputeUncertainty(problem);
    const Eigen::VectorXd dense = DenseSigma(problem, u.scale);
    ASSERT_EQ(u.sigma.size(), dense.size()) << job;
    for (Eigen::Index i = 0; i < dense.size(); ++i) {
      EXPECT_NEAR(u.sigma[i], dense[i], 1e-6 * dense[i]) << job << ": " << u.names[i];
    }
  }
}

// The sandwich from sparse cluster scores (S^T S) against the dense sum over clusters of
// (J_g^T r_g)(J_g^T r_g)^T, with every seventh block its own cluster.
TEST(SparsePath, ClusterRobustCovarianceIsTheDenseSandwich) {
  Solved solved = Solve("configs/jobs/vsb_sim_b.yaml");
  Problem& problem = solved.assembled->problem;
  const Linearization at = Linearize(problem);
  const Uncertainty model = ComputeUncertainty(problem, at);
  const auto& rows = problem.residual_rows();
  std::vector<int> cluster_of_block(rows.size());
  for (size_t b = 0; b < rows.size(); ++b) cluster_of_block[b] = b % 7 == 0 ? -1 : int(b / 5);
  const Eigen::MatrixXd sandwich = ClusterRobustCovariance(problem, at, cluster_of_block, model);

  const Eigen::MatrixXd J(at.jacobian);
  const Eigen::VectorXd& r = at.residuals;
  std::map<int, Eigen::VectorXd> score;
  int own = -1;
  for (size_t b = 0; b < rows.size(); ++b) {
    const int end = b + 1 < rows.size() ? rows[b + 1] : static_cast<int>(r.size());
    const int g = cluster_of_block[b] >= 0 ? cluster_of_block[b] : own--;
    if (!score.count(g)) score[g] = Eigen::VectorXd::Zero(J.cols());
    const int n = end - rows[b];
    score[g] += J.middleRows(rows[b], n).transpose() * r.segment(rows[b], n);
  }
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(J.cols(), J.cols());
  for (const auto& [g, s] : score) meat += s * s.transpose();
  const double G = static_cast<double>(score.size());
  const Eigen::MatrixXd& bread = model.inverse_information;
  const Eigen::MatrixXd dense = bread * meat * bread * (G / (G - 1));
  EXPECT_LT((sandwich - dense).norm(), 1e-10 * dense.norm());
}

}  // namespace
}  // namespace cellmetry
