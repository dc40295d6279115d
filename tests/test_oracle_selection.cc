// The oracle's Bayes choice (oracle_selection.h): its draws through the candidates' bases give
// the share of right choices that drawing the noise in every row gives, and on two orthogonal
// one-column candidates the share the normal integral gives.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "oracle_draws.h"

namespace cellmetry {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::VectorXd Unit(int rows, int index) { return Eigen::VectorXd::Unit(rows, index); }

// P(|S + x| > |y|), x and y standard normal: the right choice's share between two orthogonal
// one-column candidates when the first carries a mismatch of norm S (trapezoid rule on x).
double RightShareOfTwoOrthogonal(double S) {
  double sum = 0.0;
  const double h = 1e-3;
  for (double x = -10.0; x <= 10.0; x += h) {
    const double density = std::exp(-0.5 * x * x) / std::sqrt(2 * kPi);
    sum += density * std::erf(std::abs(S + x) / std::sqrt(2.0)) * h;
  }
  return sum;
}

TEST(OracleSelection, TwoOrthogonalCandidatesAsTheNormalIntegralSays) {
  for (double S : {0.5, 1.5, 3.0}) {
    std::vector<OracleChoice> choices = {{Unit(40, 3), true}, {Unit(40, 17), false}};
    OracleSelectionOptions options;
    options.draws = 40000;
    OracleSelection out;
    DrawBayesChoices(choices, S * Unit(40, 3), options, &out);
    const double expected = RightShareOfTwoOrthogonal(S);
    const double se = std::sqrt(expected * (1 - expected) / options.draws);
    EXPECT_NEAR(out.right_share(), expected, 4 * se + 1e-3) << "S = " << S;
  }
}

// Three candidates in 60 rows, two of them alike (0.9) and one of two columns: the draws of
// z = G^T e from G^T G's eigen-decomposition against e drawn in every row, the same formula.
TEST(OracleSelection, DrawsThroughTheBasesAgreeWithNoiseInEveryRow) {
  const int rows = 60;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  auto random_vector = [&] {
    Eigen::VectorXd v(rows);
    for (int i = 0; i < rows; ++i) v[i] = normal(rng);
    return v;
  };
  const Eigen::VectorXd u1 = random_vector().normalized();
  Eigen::VectorXd other = random_vector();
  other -= u1 * u1.dot(other);
  const Eigen::VectorXd u2 = 0.9 * u1 + std::sqrt(1 - 0.81) * other.normalized();
  Eigen::MatrixXd two(rows, 2);
  two << random_vector(), random_vector();
  const Eigen::MatrixXd U3 = Eigen::HouseholderQR<Eigen::MatrixXd>(two).householderQ() *
                             Eigen::MatrixXd::Identity(rows, 2);
  const std::vector<OracleChoice> choices = {{u1, true}, {u2, false}, {U3, false}};
  const Eigen::VectorXd d = 2.5 * u1;  // weak enough that the two-column candidate competes
  OracleSelectionOptions options;
  options.draws = 20000;
  OracleSelection out;
  DrawBayesChoices(choices, d, options, &out);

  int right = 0, sure = 0;  // sure: the top posterior at least 0.9
  for (int draw = 0; draw < options.draws; ++draw) {
    const Eigen::VectorXd r = d + random_vector();
    Eigen::VectorXd log_p(3);
    for (int c = 0; c < 3; ++c) {
      const double k = static_cast<double>(choices[c].U.cols());
      const double tau2 = d.squaredNorm() / k;
      log_p[c] = -0.5 * k * std::log1p(tau2) +
                 0.5 * tau2 / (1 + tau2) * (choices[c].U.transpose() * r).squaredNorm();
    }
    Eigen::Index top = 0;
    const double best = log_p.maxCoeff(&top);
    right += top == 0;
    sure += 1.0 / (log_p.array() - best).exp().sum() >= 0.9;
  }
  const double expected = static_cast<double>(right) / options.draws;
  EXPECT_GT(expected, 0.5);  // the alike pair makes it a contest, not a certainty
  EXPECT_LT(expected, 0.95);
  EXPECT_NEAR(out.right_share(), expected, 0.02);
  int drawn_sure = 0;
  for (int b = 90; b < options.posterior_bins; ++b) {
    drawn_sure += out.right_by_posterior[b] + out.wrong_by_posterior[b];
  }
  EXPECT_NEAR(static_cast<double>(drawn_sure) / options.draws,
              static_cast<double>(sure) / options.draws, 0.02);
}

}  // namespace
}  // namespace cellmetry
