// The normal equations a Problem sums without storing J, and the reweighted fit built on them:
// exactly the gradient of the robust cost, its Gauss-Newton Hessian from the sparse Jacobian,
// and the Cauchy answer Ceres reaches.
#include <gtest/gtest.h>

#include <ceres/ceres.h>

#include <random>

#include "cellmetry/basics/so3_jacobians.h"
#include "cellmetry/estimation/problem.h"
#include "cellmetry/estimation/reweighted_solve.h"
#include "cellmetry/estimation/shared_prediction_cost.h"

namespace cellmetry {
namespace {

// A point p seen from a rotation about z (angle, its sine and cosine) and an offset:
// (R(angle) p + offset - measured) / sigma, three rows, two parameter blocks.
struct SeenPoint {
  Eigen::Vector3d p, measured;
  double sigma;
  template <typename T>
  bool operator()(const T* angle, const T* offset, T* r) const {
    const T c = cos(angle[0]), s = sin(angle[0]);
    const T x = c * p.x() - s * p.y() + offset[0];
    const T y = s * p.x() + c * p.y() + offset[1];
    const T z = T(p.z()) + offset[2];
    r[0] = (x - measured.x()) / sigma;
    r[1] = (y - measured.y()) / sigma;
    r[2] = (z - measured.z()) / sigma;
    return true;
  }
};

constexpr double kAngle = 0.3;
const Eigen::Vector3d kOffset(10.0, -5.0, 2.0);

Parameter Named(const std::string& name, const std::string& unit, double nominal) {
  Parameter p;
  p.name = name;
  p.unit = unit;
  p.nominal = nominal;
  return p;
}

// `points` points (200 unless said) with 0.1 mm noise, every tenth off by 20 mm; the offset's z
// held (a prior on x).
std::unique_ptr<Problem> MakeProblem(double angle, const Eigen::Vector3d& offset,
                                     double sigma = 0.1, int points = 200) {
  auto problem = std::make_unique<Problem>();
  Parameter a = Named("angle", "rad", angle);
  a.lower = -1.0;
  a.upper = 1.0;
  const int rotation = problem->AddBlock("rotation", {a});
  Parameter x = Named("x", "mm", offset.x()), y = Named("y", "mm", offset.y());
  Parameter z = Named("z", "mm", offset.z());
  x.prior_sigma = 50.0;
  z.fixed = true;
  const int shift = problem->AddBlock("offset", {x, y, z});
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::uniform_real_distribution<double> where(-100.0, 100.0);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(kAngle, Eigen::Vector3d::UnitZ()).matrix();
  for (int i = 0; i < points; ++i) {
    const Eigen::Vector3d p(where(rng), where(rng), where(rng));
    Eigen::Vector3d measured =
        R * p + kOffset + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    if (i % 10 == 0) measured += Eigen::Vector3d(20.0, -20.0, 0.0);
    auto cost = std::make_unique<ceres::AutoDiffCostFunction<SeenPoint, 3, 1, 3>>(
        new SeenPoint{p, measured, sigma});
    problem->AddResidual(std::move(cost), {rotation, shift}, ResidualInfo{});
  }
  problem->Build();
  return problem;
}

void SetCauchy(Problem* problem, double width) {
  problem->SetWhitenedRobustLoss(RobustLossKind::kCauchy, std::vector<double>(200, width));
  problem->Build();
}

// The robust normal equations of the first `num_blocks` 3-row blocks of (J, r) under a Cauchy
// loss of `width`, block by block: rho' J^T J + 2 rho'' (J^T r)(J^T r)^T where
// rho' + 2 rho'' s > 0, else rho' J^T J; the gradient rho' J^T r. Three free columns.
struct CauchySums {
  double cost = 0.0;
  Eigen::MatrixXd hessian = Eigen::MatrixXd::Zero(3, 3);
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(3);
  int corrected = 0;  // blocks whose curvature term is kept
};

CauchySums SumBlockByBlock(const Eigen::MatrixXd& J, const Eigen::VectorXd& r, int num_blocks,
                           double width) {
  const ceres::CauchyLoss cauchy(width);
  CauchySums sums;
  for (int b = 0; b < num_blocks; ++b) {
    const Eigen::MatrixXd J_b = J.middleRows(3 * b, 3);
    const Eigen::Vector3d r_b = r.segment<3>(3 * b);
    double rho[3];
    cauchy.Evaluate(r_b.squaredNorm(), rho);
    sums.cost += 0.5 * rho[0];
    sums.gradient += rho[1] * J_b.transpose() * r_b;
    sums.hessian += rho[1] * J_b.transpose() * J_b;
    if (rho[1] + 2 * rho[2] * r_b.squaredNorm() <= 0) continue;
    ++sums.corrected;
    sums.hessian += 2 * rho[2] * (J_b.transpose() * r_b) * (J_b.transpose() * r_b).transpose();
  }
  return sums;
}

TEST(NormalEquations, AreTheRobustCostsGaussNewtonTermsOfTheSparseJacobian) {
  auto problem = MakeProblem(0.299, Eigen::Vector3d(10.01, -5.01, 2.0));  // near the answer
  SetCauchy(problem.get(), 3.0);
  NormalEquations at;
  ASSERT_TRUE(problem->EvaluateNormalEquations(&at));
  Eigen::VectorXd r;
  SparseJacobian J;
  ASSERT_TRUE(problem->EvaluateSparse(&r, &J));
  const Eigen::MatrixXd dense = Eigen::MatrixXd(J);
  CauchySums expected = SumBlockByBlock(dense, r, 200, 3.0);
  EXPECT_GT(expected.corrected, 100);
  EXPECT_LT(expected.corrected, 200) << "the gross errors' blocks are beyond the Cauchy curvature";
  // The prior's row has no loss.
  const Eigen::MatrixXd J_prior = dense.bottomRows(dense.rows() - 600);
  const Eigen::VectorXd r_prior = r.tail(r.size() - 600);
  expected.cost += 0.5 * r_prior.squaredNorm();
  expected.gradient += J_prior.transpose() * r_prior;
  expected.hessian += J_prior.transpose() * J_prior;
  ASSERT_EQ(at.hessian.rows(), 3);  // angle, x, y: z is held
  EXPECT_NEAR(at.cost, expected.cost, 1e-9 * expected.cost);
  EXPECT_LT((at.hessian - expected.hessian).norm(), 1e-10 * expected.hessian.norm());
  EXPECT_LT((at.gradient - expected.gradient).norm(), 1e-10 * expected.gradient.norm());
}

// The offset pulled towards (1, 1, 1) mm: a block over one parameter block.
struct OffsetOnly {
  template <typename T>
  bool operator()(const T* offset, T* r) const {
    for (int i = 0; i < 3; ++i) r[i] = offset[i] - T(1.0);
    return true;
  }
};

// J^T J and J^T r as Ceres's dense Jacobian gives them (no loss): a reference that does not
// read the Problem's own sparse layout.
void ExpectTheDenseJacobiansSums(Problem* problem, const std::string& when) {
  NormalEquations at;
  ASSERT_TRUE(problem->EvaluateNormalEquations(&at)) << when;
  double cost = 0.0;
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  ASSERT_TRUE(problem->Evaluate(&cost, &r, &J)) << when;
  ASSERT_EQ(at.hessian.rows(), J.cols()) << when;
  const Eigen::MatrixXd expected = J.transpose() * J;
  EXPECT_LT((at.hessian - expected).norm(), 1e-10 * expected.norm()) << when;
  EXPECT_LT((at.gradient - J.transpose() * r).norm(), 1e-10 * (J.transpose() * r).norm()) << when;
}

// Build keeps the sparse layout when neither the residual blocks nor the free columns changed
// (a loss set and cleared); anything else must lay it out again.
TEST(NormalEquations, FollowWhatTheLastBuildChanged) {
  auto problem = MakeProblem(0.299, Eigen::Vector3d(10.01, -5.01, 2.0));
  ExpectTheDenseJacobiansSums(problem.get(), "as built");
  const int shift = problem->FindBlock("offset");
  problem->SetFixed(shift, 2, false);  // z freed: a fourth column
  problem->Build();
  ExpectTheDenseJacobiansSums(problem.get(), "z freed");
  SetCauchy(problem.get(), 3.0);
  problem->SetWhitenedRobustLoss(RobustLossKind::kNone, {});
  problem->Build();  // the layout kept
  ExpectTheDenseJacobiansSums(problem.get(), "a loss set and cleared");
  problem->SetFixed(problem->FindBlock("rotation"), 0, true);  // the angle held: columns move
  problem->Build();
  ExpectTheDenseJacobiansSums(problem.get(), "the angle held");
  // One more block over the offset alone, after the build: a new column pattern.
  problem->AddResidual(
      std::make_unique<ceres::AutoDiffCostFunction<OffsetOnly, 3, 3>>(new OffsetOnly), {shift},
      ResidualInfo{});
  problem->Build();
  ExpectTheDenseJacobiansSums(problem.get(), "a residual added");
}

// A point p turned by `angle` about z and shifted by `offset` (SeenPoint's chain) as a shared
// prediction: its position, or its frame's rotation Rz(angle) R0, compared with one of many
// measurements of it. The tangent is the position, or a left rotation of the prediction.
class SharedSeenPoint : public SharedPredictionCost {
 public:
  struct Chain {
    bool position;
    Eigen::Vector3d p;
    Eigen::Matrix3d R0;
  };
  SharedSeenPoint(std::shared_ptr<const Chain> chain, const Pose& measured, double sigma)
      : chain_(std::move(chain)), measured_(measured), sigma_(sigma) {
    mutable_parameter_block_sizes()->assign({1, 3});
  }
  const void* prediction_key() const override { return chain_.get(); }
  bool Predict(double const* const* parameters, Pose* prediction, double** tangent) const override {
    const double angle = parameters[0][0];
    const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).matrix();
    const Eigen::Vector3d offset(parameters[1][0], parameters[1][1], parameters[1][2]);
    prediction->t = R * chain_->p + offset;
    prediction->R = R * chain_->R0;
    if (tangent == nullptr) return true;
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d d_angle = chain_->position ? Eigen::Vector3d(z.cross(R * chain_->p)) : z;
    if (tangent[0]) std::copy(d_angle.data(), d_angle.data() + 3, tangent[0]);
    if (tangent[1]) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> d_offset(tangent[1]);
      d_offset.setZero();
      if (chain_->position) d_offset.setIdentity();
    }
    return true;
  }
  bool AffineComparison(Eigen::Vector3d* weight, Eigen::Vector3d* measured) const override {
    if (!chain_->position) return false;
    *weight = Eigen::Vector3d::Constant(1.0 / sigma_);
    *measured = measured_.t;
    return true;
  }
  void Compare(const Pose& prediction, double* residual,
               Eigen::Matrix3d* d_residual) const override {
    Eigen::Map<Eigen::Vector3d> r(residual);
    if (chain_->position) {
      r = (prediction.t - measured_.t) / sigma_;
      if (d_residual) *d_residual = Eigen::Matrix3d::Identity() / sigma_;
      return;
    }
    const Eigen::Vector3d error = RotationError<double>(prediction.R, measured_.R);
    r = error / sigma_;
    if (d_residual) *d_residual = InverseLeftJacobian(error) / sigma_;
  }

 private:
  std::shared_ptr<const Chain> chain_;
  Pose measured_;
  double sigma_;
};

// 30 points, each measured 6 times (position and rotation), the measurements of a point
// interleaved with the other points' (a unit's blocks are not consecutive); every seventh
// measurement off by 20 sigma. Blocks: the angle, the offset (z held).
std::unique_ptr<Problem> MakeSharedProblem() {
  auto problem = std::make_unique<Problem>();
  const int rotation = problem->AddBlock("rotation", {Named("angle", "rad", 0.299)});
  Parameter z = Named("z", "mm", 2.0);
  z.fixed = true;
  const int shift =
      problem->AddBlock("offset", {Named("x", "mm", 10.01), Named("y", "mm", -5.01), z});
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> where(-100.0, 100.0);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(kAngle, Eigen::Vector3d::UnitZ()).matrix();
  std::vector<std::shared_ptr<const SharedSeenPoint::Chain>> chains;
  for (int i = 0; i < 60; ++i) {
    const Eigen::Vector3d p(where(rng), where(rng), where(rng));
    const Eigen::Matrix3d R0 =
        Eigen::AngleAxisd(where(rng) / 100.0, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
    chains.push_back(
        std::make_shared<const SharedSeenPoint::Chain>(SharedSeenPoint::Chain{i % 2 == 0, p, R0}));
  }
  int count = 0;
  for (int capture = 0; capture < 6; ++capture) {
    for (const auto& chain : chains) {
      const double sigma = chain->position ? 0.1 : 0.002;
      const double gross = ++count % 7 == 0 ? 20.0 : 0.0;
      const Eigen::Vector3d e(noise(rng) + gross, noise(rng), noise(rng));
      Pose measured;
      measured.t = R * chain->p + kOffset + sigma * e;
      measured.R = RotationFromRvec<double>(Eigen::Vector3d(sigma * e).data()) * R * chain->R0;
      problem->AddResidual(std::make_unique<SharedSeenPoint>(chain, measured, sigma),
                           {rotation, shift}, ResidualInfo{});
    }
  }
  problem->Build();
  return problem;
}

// The shared predictions' sums (A^T M A) are the block-by-block ones (J^T (w + c r r^T) J from
// each block's own Evaluate), with and without a Cauchy loss whose curvature term is on for most
// blocks and off for the gross errors'.
TEST(NormalEquations, OfSharedPredictionsAreTheBlockByBlockSums) {
  auto problem = MakeSharedProblem();
  ExpectTheDenseJacobiansSums(problem.get(), "no loss");
  problem->SetWhitenedRobustLoss(RobustLossKind::kCauchy, std::vector<double>(360, 3.0));
  problem->Build();
  NormalEquations at;
  ASSERT_TRUE(problem->EvaluateNormalEquations(&at));
  // Each block on its own, as Ceres evaluates it (not the Problem's shared rows).
  Eigen::VectorXd r;
  Eigen::MatrixXd dense;
  ASSERT_TRUE(problem->Evaluate(nullptr, &r, &dense, /*apply_loss=*/false));
  const CauchySums expected = SumBlockByBlock(dense, r, 360, 3.0);
  EXPECT_GT(expected.corrected, 200);
  EXPECT_LT(expected.corrected, 360) << "the gross errors' blocks are beyond the Cauchy curvature";
  EXPECT_NEAR(at.cost, expected.cost, 1e-10 * expected.cost);
  EXPECT_LT((at.hessian - expected.hessian).norm(), 1e-10 * expected.hessian.norm());
  EXPECT_LT((at.gradient - expected.gradient).norm(), 1e-10 * expected.gradient.norm());
}

// One prediction key over two lists of parameter blocks, alternating as they are added (a
// cost's key should say what it predicts from; this one does not say which offset): blocks
// share a prediction only with blocks over the same list, never across.
TEST(NormalEquations, ShareAPredictionOnlyOverTheSameParameterBlocks) {
  auto problem = std::make_unique<Problem>();
  const int rotation = problem->AddBlock("rotation", {Named("angle", "rad", 0.2)});
  const int first = problem->AddBlock(
      "first", {Named("x", "mm", 1.0), Named("y", "mm", 2.0), Named("z", "mm", 3.0)});
  const int second = problem->AddBlock(
      "second", {Named("x", "mm", -1.0), Named("y", "mm", 4.0), Named("z", "mm", 5.0)});
  const auto chain = std::make_shared<const SharedSeenPoint::Chain>(SharedSeenPoint::Chain{
      true, Eigen::Vector3d(30.0, -20.0, 10.0), Eigen::Matrix3d::Identity()});
  for (int i = 0; i < 8; ++i) {
    Pose measured;
    measured.t = Eigen::Vector3d(i, 2.0 * i, -i);
    problem->AddResidual(std::make_unique<SharedSeenPoint>(chain, measured, 0.5),
                         {rotation, i % 2 == 0 ? first : second}, ResidualInfo{});
  }
  problem->Build();
  ExpectTheDenseJacobiansSums(problem.get(), "alternating blocks");
}

// The sparse Jacobian's rows of shared predictions (one Predict, each block's D A) are Ceres's
// (each unit one block of it, its rows put back in the Problem's order by Evaluate), and both
// differentiate the residuals: against central differences.
TEST(SharedPredictionCost, JacobianIsTheResidualsByCentralDifferences) {
  auto problem = MakeSharedProblem();
  Eigen::VectorXd r, r_ceres;
  SparseJacobian J;
  ASSERT_TRUE(problem->EvaluateSparse(&r, &J));
  const Eigen::MatrixXd dense = Eigen::MatrixXd(J);
  Eigen::MatrixXd ceres_dense;
  ASSERT_TRUE(problem->Evaluate(nullptr, &r_ceres, &ceres_dense, /*apply_loss=*/false));
  EXPECT_LT((r - r_ceres).norm(), 1e-12 * r.norm());
  EXPECT_LT((dense - ceres_dense).norm(), 1e-12 * dense.norm());
  const Eigen::VectorXd x = problem->FreeValues();
  for (int c = 0; c < x.size(); ++c) {
    const double h = 1e-6;
    Eigen::VectorXd plus = x, minus = x, r_plus, r_minus;
    plus[c] += h;
    minus[c] -= h;
    problem->SetFreeValues(plus);
    ASSERT_TRUE(problem->EvaluateSparse(&r_plus, nullptr));
    problem->SetFreeValues(minus);
    ASSERT_TRUE(problem->EvaluateSparse(&r_minus, nullptr));
    const Eigen::VectorXd numeric = (r_plus - r_minus) / (2 * h);
    EXPECT_LT((dense.col(c) - numeric).cwiseAbs().maxCoeff(), 1e-5 * numeric.norm())
        << problem->free_parameters()[c].name;
  }
  problem->SetFreeValues(x);
}

TEST(NormalEquations, GradientIsTheRobustCostsOwnByCentralDifferences) {
  auto problem = MakeProblem(0.25, Eigen::Vector3d(9.0, -4.0, 2.0));
  SetCauchy(problem.get(), 3.0);
  NormalEquations at;
  ASSERT_TRUE(problem->EvaluateNormalEquations(&at));
  const Eigen::VectorXd x = problem->FreeValues();
  for (int i = 0; i < x.size(); ++i) {
    const double h = 1e-6;
    NormalEquations plus, minus;
    Eigen::VectorXd moved = x;
    moved[i] += h;
    problem->SetFreeValues(moved);
    ASSERT_TRUE(problem->EvaluateNormalEquations(&plus));
    moved[i] = x[i] - h;
    problem->SetFreeValues(moved);
    ASSERT_TRUE(problem->EvaluateNormalEquations(&minus));
    const double numeric = (plus.cost - minus.cost) / (2 * h);
    EXPECT_NEAR(at.gradient[i], numeric, 1e-6 * std::max(1.0, std::abs(numeric))) << i;
  }
}

// 20,000 blocks: split into many ranges summed on both cores, whose partial sums a
// non-deterministic reduce would add in an order that varies from call to call.
TEST(NormalEquations, SumInTheSameOrderOnEveryCall) {
  auto problem = MakeProblem(0.25, Eigen::Vector3d(9.0, -4.0, 2.0), 0.1, 20000);
  NormalEquations first, second;
  ASSERT_TRUE(problem->EvaluateNormalEquations(&first));
  for (int call = 0; call < 20; ++call) {
    ASSERT_TRUE(problem->EvaluateNormalEquations(&second));
    EXPECT_EQ(first.cost, second.cost);
    EXPECT_TRUE((first.hessian.array() == second.hessian.array()).all());
    EXPECT_TRUE((first.gradient.array() == second.gradient.array()).all());
  }
}

// Ceres's Levenberg-Marquardt with the same loss, to its tightest tolerances, on the Problem's
// rows or (`summed`) on the view a solver gets; its final cost into `final_cost` if asked.
Eigen::VectorXd CeresAnswer(Problem* problem, bool summed = false, double* final_cost = nullptr) {
  ceres::Solver::Options options;
  options.function_tolerance = options.gradient_tolerance = 1e-15;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, summed ? &problem->ceres_problem_for_solving() : &problem->ceres_problem(),
               &summary);
  EXPECT_EQ(summary.termination_type, ceres::CONVERGENCE);
  if (final_cost) *final_cost = summary.final_cost;
  return problem->FreeValues();
}

TEST(ReweightedSolve, ReachesTheCauchyAnswerOfCeresFromTheLeastSquaresOne) {
  auto ours = MakeProblem(0.0, Eigen::Vector3d(0.0, 0.0, 2.0));
  const Eigen::VectorXd least_squares = CeresAnswer(ours.get());
  // The gross errors pull least squares by about 2 mm; the robust answer is within noise.
  EXPECT_GT((least_squares.tail(2) - kOffset.head(2)).norm(), 1.0);
  SetCauchy(ours.get(), 3.0);
  const SolverSummary summary = SolveByReweighting(ours.get());
  EXPECT_TRUE(summary.converged) << summary.stop_reason;
  EXPECT_LT(summary.iterations, 20);
  auto theirs = MakeProblem(0.0, Eigen::Vector3d(0.0, 0.0, 2.0));
  theirs->SetFreeValues(least_squares);
  SetCauchy(theirs.get(), 3.0);
  const Eigen::VectorXd cauchy = CeresAnswer(theirs.get());
  // Within 0.014 of sigma, the tolerance's promise: sigma here ~ 0.1 / sqrt(180) mm, 1e-4 rad.
  NormalEquations at;
  ASSERT_TRUE(ours->EvaluateNormalEquations(&at));
  const Eigen::VectorXd difference = ours->FreeValues() - cauchy;
  EXPECT_LT(std::sqrt(difference.dot(at.hessian * difference)), 0.014 * std::sqrt(2.0));
  EXPECT_LT((ours->FreeValues().tail(2) - kOffset.head(2)).norm(), 0.05);
}

TEST(ReweightedSolve, WithoutALossIsLeastSquares) {
  auto ours = MakeProblem(0.0, Eigen::Vector3d(0.0, 0.0, 2.0));
  ReweightedSolveOptions tight;
  tight.decrement_tolerance = 1e-16;
  tight.max_iterations = 100;
  const SolverSummary summary = SolveByReweighting(ours.get(), tight);
  auto theirs = MakeProblem(0.0, Eigen::Vector3d(0.0, 0.0, 2.0));
  const Eigen::VectorXd expected = CeresAnswer(theirs.get());
  EXPECT_TRUE(summary.converged) << summary.stop_reason;
  EXPECT_LT((ours->FreeValues() - expected).cwiseAbs().maxCoeff(), 1e-9);
}

// Without a loss, Ceres gets each unit of blocks sharing a prediction as one residual block
// (shared_prediction_group.h) and reaches the least-squares answer; with a loss on every block,
// each block is its own again (a capture's loss must see its own norm), with the same cost.
TEST(SharedPredictionGroup, CeresSolvesAUnitAsOneBlockWithoutALoss) {
  auto grouped = MakeSharedProblem();
  EXPECT_EQ(grouped->ceres_problem().NumResidualBlocks(), 60) << "60 points, 6 captures each";
  EXPECT_EQ(grouped->ceres_problem().NumResiduals(), 1080);
  const Eigen::VectorXd answer = CeresAnswer(grouped.get());
  auto reweighted = MakeSharedProblem();
  ReweightedSolveOptions tight;
  tight.decrement_tolerance = 1e-16;
  tight.max_iterations = 100;
  EXPECT_TRUE(SolveByReweighting(reweighted.get(), tight).converged);
  EXPECT_LT((answer - reweighted->FreeValues()).cwiseAbs().maxCoeff(), 1e-9);

  double grouped_cost = 0.0;
  ASSERT_TRUE(grouped->Evaluate(&grouped_cost, nullptr, nullptr));
  grouped->SetWhitenedRobustLoss(RobustLossKind::kCauchy, std::vector<double>(360, 1e12));
  grouped->Build();
  EXPECT_EQ(grouped->ceres_problem().NumResidualBlocks(), 360);
  double block_cost = 0.0;
  ASSERT_TRUE(grouped->Evaluate(&block_cost, nullptr, nullptr, /*apply_loss=*/false));
  EXPECT_NEAR(block_cost, grouped_cost, 1e-12 * grouped_cost);
}

// A unit of 200 captures (a static camera's views of the world tag) reaches Ceres in pieces of
// at most 64 members, which its threads share; the rows Evaluate() returns are still each
// block's own, in the Problem's order.
TEST(SharedPredictionGroup, ALargeUnitReachesCeresInPieces) {
  auto problem = std::make_unique<Problem>();
  const int rotation = problem->AddBlock("rotation", {Named("angle", "rad", 0.1)});
  const int shift = problem->AddBlock(
      "offset", {Named("x", "mm", 1.0), Named("y", "mm", 2.0), Named("z", "mm", 3.0)});
  const auto chain = std::make_shared<const SharedSeenPoint::Chain>(SharedSeenPoint::Chain{
      false, Eigen::Vector3d(30.0, -20.0, 10.0), Eigen::Matrix3d::Identity()});
  std::vector<const SharedSeenPoint*> costs;
  for (int i = 0; i < 200; ++i) {
    Pose measured;
    measured.R = Eigen::AngleAxisd(0.001 * i, Eigen::Vector3d::UnitX()).matrix();
    auto cost = std::make_unique<SharedSeenPoint>(chain, measured, 0.01);
    costs.push_back(cost.get());
    problem->AddResidual(std::move(cost), {rotation, shift}, ResidualInfo{});
  }
  problem->Build();
  EXPECT_EQ(problem->ceres_problem().NumResidualBlocks(), 4) << "64 + 64 + 64 + 8";
  Eigen::VectorXd r;
  ASSERT_TRUE(problem->Evaluate(nullptr, &r, nullptr));
  const double* parameters[] = {problem->values(rotation), problem->values(shift)};
  for (int i = 0; i < 200; ++i) {
    Eigen::Vector3d own;
    ASSERT_TRUE(costs[i]->Evaluate(parameters, own.data(), nullptr));
    EXPECT_LT((r.segment<3>(3 * i) - own).norm(), 1e-12) << i;
  }
}

// Cost and gradient of a ceres::Problem over every free block, at the current values.
double CeresCost(ceres::Problem& problem, std::vector<double>* gradient) {
  double cost = 0.0;
  EXPECT_TRUE(
      problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, gradient, nullptr));
  return cost;
}

// The view Ceres solves sums each unit of positions into 3 rows (summed_position_group.h):
// at any values its cost and gradient are the rows' own, and Ceres reaches the same answer,
// reporting the same cost, over 58 % of the rows (631 of 1,080).
TEST(SummedPositionGroup, SolvesTheSameProblemOverFewerRows) {
  auto problem = MakeSharedProblem();
  ceres::Problem& rows = problem->ceres_problem();
  ceres::Problem& summed = problem->ceres_problem_for_solving();
  // 30 position units of 6 captures: 3 rows each, not 18; 30 rotation units as they were; and
  // the constant's row.
  EXPECT_EQ(summed.NumResiduals(), 30 * 3 + 30 * 18 + 1);
  EXPECT_EQ(rows.NumResiduals(), 1080);
  const Eigen::VectorXd start = problem->FreeValues();
  for (int step = 0; step < 4; ++step) {
    Eigen::VectorXd x = start;
    x[0] += 0.05 * step;
    x[1] -= 3.0 * step;
    problem->SetFreeValues(x);
    std::vector<double> gradient_rows, gradient_summed;
    const double cost_rows = CeresCost(rows, &gradient_rows);
    const double cost_summed = CeresCost(summed, &gradient_summed);
    EXPECT_NEAR(cost_summed, cost_rows, 1e-12 * cost_rows) << step;
    ASSERT_EQ(gradient_rows.size(), gradient_summed.size());
    for (size_t i = 0; i < gradient_rows.size(); ++i) {
      EXPECT_NEAR(gradient_summed[i], gradient_rows[i], 1e-9 * (1.0 + std::abs(gradient_rows[i])))
          << step << " " << i;
    }
  }
  problem->SetFreeValues(start);
  const Eigen::VectorXd rows_answer = CeresAnswer(problem.get());
  problem->SetFreeValues(start);
  double final_cost = 0.0;
  const Eigen::VectorXd summed_answer = CeresAnswer(problem.get(), /*summed=*/true, &final_cost);
  EXPECT_LT((summed_answer - rows_answer).cwiseAbs().maxCoeff(), 1e-9);
  double cost = 0.0;
  ASSERT_TRUE(problem->Evaluate(&cost, nullptr, nullptr));
  EXPECT_NEAR(final_cost, cost, 1e-12 * cost);
}

// With a loss on every block nothing is summed (each capture's loss sees its own norm), and a
// Build drops the view made before it.
TEST(SummedPositionGroup, NothingIsSummedUnderARobustLoss) {
  auto problem = MakeSharedProblem();
  EXPECT_LT(problem->ceres_problem_for_solving().NumResiduals(), 1080);
  problem->SetWhitenedRobustLoss(RobustLossKind::kCauchy, std::vector<double>(360, 3.0));
  problem->Build();
  EXPECT_EQ(problem->ceres_problem_for_solving().NumResidualBlocks(), 360);
  EXPECT_EQ(problem->ceres_problem_for_solving().NumResiduals(), 1080);
}

// A cost of about 1e13 (the gross errors over a 1e-5 mm sigma) cannot show a decrease of 1e-10:
// at its minimum the solve says converged, not "no step lowers the cost".
TEST(ReweightedSolve, ConvergesWhereTheCostCannotResolveTheTolerance) {
  auto problem = MakeProblem(0.0, Eigen::Vector3d(0.0, 0.0, 2.0), 1e-5);
  ReweightedSolveOptions tight;
  tight.decrement_tolerance = 1e-10;
  const SolverSummary summary = SolveByReweighting(problem.get(), tight);
  EXPECT_GT(summary.final_cost, 1e12);
  EXPECT_TRUE(summary.converged) << summary.stop_reason;
  auto reference = MakeProblem(0.0, Eigen::Vector3d(0.0, 0.0, 2.0), 1e-5);
  const Eigen::VectorXd expected = CeresAnswer(reference.get());
  EXPECT_LT((problem->FreeValues() - expected).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(ReweightedSolve, SaysWhenTheStartCannotBeEvaluated) {
  auto problem = MakeProblem(0.0, Eigen::Vector3d(0.0, 0.0, 2.0));
  problem->values(1)[0] = std::nan("");
  const SolverSummary summary = SolveByReweighting(problem.get());
  EXPECT_FALSE(summary.converged);
  EXPECT_FALSE(std::isfinite(summary.final_cost));
}

}  // namespace
}  // namespace cellmetry
