// The physics finder's statistics against textbook values, and the small text helpers of
// basics.
#include <gtest/gtest.h>

#include <cmath>

#include "cellmetry/basics/statistics.h"
#include "cellmetry/basics/text.h"

namespace cellmetry {
namespace {

TEST(Statistics, ChiSquareTailsMatchTables) {
  EXPECT_NEAR(ChiSquareSurvival(3.841459, 1), 0.05, 1e-6);
  EXPECT_NEAR(ChiSquareSurvival(6.634897, 1), 0.01, 1e-7);
  EXPECT_NEAR(ChiSquareSurvival(18.307038, 10), 0.05, 1e-6);
  EXPECT_NEAR(ChiSquareSurvival(3000.0, 3000), 0.4949, 2e-3);  // about the median
  EXPECT_DOUBLE_EQ(ChiSquareSurvival(0.0, 4), 1.0);
  // Far in the tail the log stays exact where the probability underflows: for k = 2,
  // P(X > x) = exp(-x / 2) exactly.
  EXPECT_NEAR(ChiSquareLogSurvival(4000.0, 2), -2000.0, 1e-9);
  EXPECT_NEAR(ChiSquareLogSurvival(18.307038, 10), std::log(0.05), 1e-5);
}

TEST(Statistics, NormalTail) {
  EXPECT_NEAR(NormalSurvival(1.959964), 0.025, 1e-7);
  EXPECT_NEAR(NormalSurvival(0.0), 0.5, 1e-15);
}

TEST(Statistics, HolmStepsDownAndStaysMonotone) {
  // Holm (1979): sorted p 0.01, 0.02, 0.04 of three -> 0.03, 0.04, 0.04.
  const auto adjusted = HolmAdjusted({0.04, 0.01, 0.02});
  EXPECT_NEAR(adjusted[1], 0.03, 1e-15);
  EXPECT_NEAR(adjusted[2], 0.04, 1e-15);
  EXPECT_NEAR(adjusted[0], 0.04, 1e-15);
  EXPECT_DOUBLE_EQ(HolmAdjusted({0.9, 0.8})[0], 1.0);  // capped at 1
}

TEST(Statistics, DurbinWatsonSeesDrift) {
  std::vector<double> alternating, drifting;
  for (int i = 0; i < 100; ++i) {
    alternating.push_back(i % 2 ? 1.0 : -1.0);
    drifting.push_back(std::sin(i * 0.05));
  }
  EXPECT_NEAR(DurbinWatson(alternating), 4.0, 0.05);  // negative correlation
  EXPECT_LT(DurbinWatson(drifting), 0.1);             // slow drift
}

TEST(Statistics, MedianOfOddAndEvenCounts) {
  EXPECT_DOUBLE_EQ(Median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(Median({4.0, 1.0, 3.0, 2.0}), 2.5);  // the two middle values' mean
  EXPECT_DOUBLE_EQ(Median({-1.0}), -1.0);
  EXPECT_TRUE(std::isnan(Median({})));
}

TEST(Statistics, UpperMedianTakesTheUpperMiddleInPlace) {
  std::vector<double> odd = {3.0, 1.0, 2.0}, even = {4.0, 1.0, 3.0, 2.0}, none;
  EXPECT_DOUBLE_EQ(UpperMedian(&odd), 2.0);
  EXPECT_DOUBLE_EQ(UpperMedian(&even), 3.0);  // not the mean of 2 and 3
  EXPECT_EQ(even.size(), 4u);                 // reordered, nothing dropped
  EXPECT_TRUE(std::isnan(UpperMedian(&none)));
}

TEST(Statistics, CorrelationOfACovariance) {
  Eigen::MatrixXd covariance(3, 3);
  covariance << 4.0, 3.0, 0.0,  //
      3.0, 9.0, 0.0,            //
      0.0, 0.0, 0.0;            // the third entry has no spread
  const Eigen::MatrixXd correlation = CorrelationOf(covariance);
  EXPECT_DOUBLE_EQ(correlation(0, 0), 1.0);
  EXPECT_DOUBLE_EQ(correlation(0, 1), 0.5);  // 3 / (2 * 3)
  EXPECT_DOUBLE_EQ(correlation(1, 0), 0.5);
  EXPECT_DOUBLE_EQ(correlation(2, 2), 1.0);
  EXPECT_DOUBLE_EQ(correlation(0, 2), 0.0);
}

TEST(Text, JoinAndMillimetres) {
  EXPECT_EQ(Join({"x", "y", "z"}), "x, y, z");
  EXPECT_EQ(Join({"a", "b"}, " / "), "a / b");
  EXPECT_EQ(Join({}), "");
  EXPECT_EQ(Mm(12.3456), "12.3 mm");
  EXPECT_EQ(Mm(12.3456, 4), "12.35 mm");
  EXPECT_EQ(Mm(0.00012), "0.00012 mm");
}

}  // namespace
}  // namespace cellmetry
