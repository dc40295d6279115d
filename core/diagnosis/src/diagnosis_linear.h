// The physics finder's linear algebra (internal to the core): a fitted workcell linearized at
// its estimate, with one candidate effect added at zero, and what follows from it without
// refitting: how much of the candidate's signature the geometry absorbs, its score statistic,
// bootstrap resamples of poses, and partial correlations with regressors.
//
// Everything is in whitened units (residuals over sigma), where the score statistic of a
// candidate with Jacobian columns J_e, after projecting out the span of the current model's
// Jacobian J_g, is  S = r^T P (P^T P)^+ P^T r  with P = (I - Q Q^T) J_e, Q an orthonormal basis
// of span(J_g): the likelihood-ratio statistic to first order (Rao's score test), chi-square
// with rank(P) degrees of freedom when the candidate is absent.
#pragma once

#include <Eigen/Core>
#include <random>
#include <string>
#include <vector>

#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/estimation/noise_model.h"

namespace cellmetry {

// What one residual row is: its block's kind and sigma (the problem's ResidualInfo) and what
// it measured (the assembly's label; a prior's is the default, observation and pose -1).
struct CandidateRow {
  ResidualInfo::Kind kind = ResidualInfo::Kind::kPrior;
  Eigen::Vector3d sigma = Eigen::Vector3d::Ones();
  MeasurementLabel label;
};

struct CandidateLinearization {
  Eigen::VectorXd r;               // whitened residuals at the estimate
  Eigen::MatrixXd J_model;         // columns of the current model's free parameters
  Eigen::MatrixXd J_candidate;     // columns of the candidate's parameters (none: 0 columns)
  std::vector<CandidateRow> rows;  // per residual row: its block's
  std::vector<int> row_axis;       // 0, 1, 2: the camera axis of the row
};

// `spec` already holds the candidate as its last effect when `candidate` is true.
CandidateLinearization LinearizeWithCandidate(const WorkcellProblem& spec,
                                              const Recording& recording, const WorkcellData& data,
                                              const NoiseModel& noise,
                                              const WorkcellEstimate& estimate, bool candidate);

// Every candidate's Jacobian columns from one linearization of the current model: `spec` with
// all of `candidates` added at zero, evaluated once at `estimate` and differentiated only with
// respect to the candidates' parameters (Problem::EvaluateSparseColumns: a candidate's columns
// are filled only on the rows it acts on, and the model's columns are not computed again).
// An effect at zero leaves the prediction as it is, so each one's columns are those it has
// when added alone (LinearizeWithCandidate's J_candidate), over the current model's first
// `rows` rows (its measurements and priors; a candidate's own priors are left out).
std::vector<Eigen::MatrixXd> CandidateColumns(const WorkcellProblem& spec,
                                              const std::vector<WorkcellEffect>& candidates,
                                              const Recording& recording, const WorkcellData& data,
                                              const NoiseModel& noise,
                                              const WorkcellEstimate& estimate, Eigen::Index rows);

// An orthonormal basis of the columns' span (rank-revealing QR).
Eigen::MatrixXd OrthonormalBasis(const Eigen::MatrixXd& columns);

// X minus its projection onto span(Q) (Q orthonormal).
Eigen::MatrixXd ProjectOut(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& X);

// Largest canonical correlation of two subspaces given by orthonormal bases (of two candidates'
// unabsorbed signatures: how alike the poses leave them): the cosine of the smallest angle
// between them; 0 when either is empty.
double CanonicalCorrelation(const Eigen::MatrixXd& U_a, const Eigen::MatrixXd& U_b);

// An orthonormal basis of what the current model leaves of a candidate's columns `J` (`P` =
// ProjectOut(Q_model, J)): P's left singular vectors above 1e-6 of the candidate's own scale
// ||J||_F, smaller directions carrying no information. Its columns are the score test's degrees
// of freedom.
Eigen::MatrixXd UnabsorbedBasis(const Eigen::MatrixXd& J, const Eigen::MatrixXd& P);

// How strongly a chi-square statistic with `dof` degrees of freedom speaks against "no effect"
// (-ln of its p-value), comparable across dof even where the p-value underflows.
double Strength(double statistic, int dof);

// A map of standard normals to draws with `covariance` (positive semi-definite, as a stack of
// bases' Gram matrix is): from covariance = V L V^T, the map V sqrt(L).
Eigen::MatrixXd NormalDrawMap(const Eigen::MatrixXd& covariance);

// The score statistic a candidate would add at its plausible size: the largest |P D u|^2 over
// unit u, D = diag(each parameter's Parameter::plausible), `P` its unabsorbed columns
// (whitened): sigma_max(P D)^2, the noncentrality of its score test in the direction these
// poses show best. NaN where a parameter has no plausible size.
double PlausibleNoncentrality(const Eigen::MatrixXd& P, const std::vector<Parameter>& parameters);

struct ScoreTest {
  double unabsorbed = 0.0;  // ||P||_F / ||J_e||_F
  double statistic = 0.0;
  int dof = 0;
  double p_value = 1.0;
};

// The size a candidate has were it alone the cause of the residuals `r` (whitened, at the
// current model's answer, so orthogonal to the model's span): the least-squares solution of
// P theta = r, `P` = ProjectOut(Q_model, J_candidate), in the candidate's parameter units;
// directions P cannot see (rank-deficient) at zero. The linearized refit: what RivalTestP takes
// as the rival's size, in numbers a plausibility range can judge.
Eigen::VectorXd UnabsorbedSize(const Eigen::MatrixXd& P, const Eigen::VectorXd& r);

// `P` = ProjectOut(Q_model, J_candidate); `r` the residuals.
ScoreTest Score(const Eigen::VectorXd& r, const Eigen::MatrixXd& J_candidate,
                const Eigen::MatrixXd& P);

// The chosen candidate against one rival, each as the whole mismatch (non-nested models; Cox
// 1962, "Further results on tests of separate families of hypotheses", JRSS B 24; by parametric
// bootstrap, Williams 1970, "Discrimination between regression models to determine the pattern
// of enzyme synthesis", Biometrics 26). The margin is the chosen one's strength (-ln p of its
// score statistic) less the rival's. Under the rival as the truth, its signature at the size the
// data give it (U_rival U_rival^T r) plus whitened noise, the margin is drawn `draws` times in
// the span of the two bases (z = [U_c U_r]^T r, normal with covariance [[I, C], [C^T, I]],
// C = U_c^T U_r); the p-value is the share of draws whose margin is at least the data's (with
// the usual +1 in both counts). A small p: were the rival the cause, the chosen one would
// rarely win by this much. 1 when the rival is as strong as the chosen one or stronger.
double RivalTestP(const Eigen::VectorXd& r, const Eigen::MatrixXd& U_chosen,
                  const Eigen::MatrixXd& U_rival, int draws, unsigned seed);

// RivalTestP for a decision at `alpha` that the draws do not make: where the p of `draws` draws
// lies within three Monte Carlo standard errors of alpha (sqrt(alpha (1 - alpha) / draws):
// 0.0022 at 2,000 draws and 1 %), it is drawn again with 20 times as many (SE 0.0005), so
// that which side of alpha it falls on is the data's (a two-stage Monte Carlo test; the risk
// it bounds, a decision that differs from the exact p's, is Gandy 2009, "Sequential
// implementation of Monte Carlo tests with uniformly bounded resampling risk", JASA 104).
double RivalTestPAt(double alpha, const Eigen::VectorXd& r, const Eigen::MatrixXd& U_chosen,
                    const Eigen::MatrixXd& U_rival, int draws, unsigned seed);

// Bootstrap inclusion (Sauerbrei & Schumacher 1992) on the linearization: resample poses with
// replacement, refit the current model's linear part on the resample, and run the greedy
// selection there: the candidate whose score statistic speaks most strongly (the smallest log
// p-value, comparable across degrees of freedom) is included when it lowers BIC to first order
// (statistic > dof * `penalty_per_dof`, ln of the rows); its columns join the model and the
// next step scores the rest, for up to `max_steps` inclusions. What the bootstrap measures is
// which effect the data picks, not whether it is significant (the full data's likelihood-ratio
// test with Holm's correction says that); a Holm gate on resamples, whose statistics scatter
// about twice as widely as the data's, dropped real effects at SNR 6 in a quarter of resamples.
// Counting inclusion rather than first place keeps a chance winner of one resample (a signature
// concentrated on few poses swings most under resampling) from voting the real effect out.
// Returns, per resample, the indices (into `candidates`) it included.
//
// How: everything the selection computes (projections, norms, singular values, inner products)
// depends on a resample's rows only through their cross products, so each resample runs on an
// (N x N) matrix B with B^T B = A^T W A, A = [J_model, candidates, r] (N columns) and W the
// resample's pose counts, instead of on its thousands of rows. A = Q R once (Householder);
// then A^T W A = R^T (Q^T W Q) R, and Q^T W Q = sum over poses of count x Q_p^T Q_p, summed
// from per-pose blocks computed once, is factored (pivoted LDL^T) into F^T F: B = F R. The ill
// conditioning of J stays in R, never squared; the factored matrix is a reweighted identity.
// Columns that no drawn pose supports are exactly zero, as in the rows. Resamples run in
// parallel, each on its counts drawn in order from `seed`: the result does not depend on the
// threads.
std::vector<std::vector<int>> BootstrapInclusions(const Eigen::VectorXd& r,
                                                  const Eigen::MatrixXd& J_model,
                                                  const std::vector<Eigen::MatrixXd>& candidates,
                                                  const std::vector<int>& row_pose, int resamples,
                                                  double penalty_per_dof, int max_steps,
                                                  unsigned seed);

// The same selection on each resample's reweighted rows as they are (sqrt(count) times each
// row): the reference the compressed form above must agree with, and its path where there are
// no more rows than columns.
std::vector<std::vector<int>> BootstrapInclusionsOnRows(
    const Eigen::VectorXd& r, const Eigen::MatrixXd& J_model,
    const std::vector<Eigen::MatrixXd>& candidates, const std::vector<int>& row_pose, int resamples,
    double penalty_per_dof, int max_steps, unsigned seed);

}  // namespace cellmetry
