// The physics finder's statistics against textbook values, and the small text helpers of
// basics.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "cellmetry/basics/statistics.h"
#include "cellmetry/basics/text.h"
#include "cellmetry/basics/utf8.h"

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

// The sample standard deviation of v: a Monte Carlo's spread.
double SampleSpread(const std::vector<double>& v) {
  double mean = 0.0, squares = 0.0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  for (double x : v) squares += (x - mean) * (x - mean);
  return std::sqrt(squares / static_cast<double>(v.size() - 1));
}

// The standard errors against their own Monte Carlo: 4,000 experiments of 100 points with 3D
// errors N(0, s^2 I). The spread of the RMS over the experiments is s / sqrt(2 n) in theory, and
// the mean reported standard error must match that spread. Paired: the same points under a second
// model that removes a part of each error, whose gain's spread the paired error must match; it
// is well below what the two RMS's own errors would suggest.
TEST(Statistics, RmsStandardErrorsMatchTheirMonteCarloSpread) {
  constexpr int kExperiments = 4000;
  constexpr int kPoints = 100;
  constexpr double kSigma = 0.05;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, kSigma);
  std::vector<double> rms, gains;
  double se_sum = 0.0, after_se_sum = 0.0, gain_se_sum = 0.0;
  for (int e = 0; e < kExperiments; ++e) {
    std::vector<double> before(kPoints), after(kPoints);
    for (int i = 0; i < kPoints; ++i) {
      double b2 = 0.0, a2 = 0.0;
      for (int axis = 0; axis < 3; ++axis) {
        const double kept = noise(rng), removed = 0.5 * noise(rng);
        b2 += (kept + removed) * (kept + removed);
        a2 += kept * kept;
      }
      before[i] = b2;
      after[i] = a2;
    }
    const RmsEstimate b = RmsWithStandardError(before);
    const RmsEstimate a = RmsWithStandardError(after);
    rms.push_back(b.rms);
    se_sum += b.standard_error;
    after_se_sum += a.standard_error;
    gains.push_back(b.rms - a.rms);
    gain_se_sum += RmsDifferenceStandardError(before, after);
  }
  const double theory = kSigma * std::sqrt(1.25) / std::sqrt(2.0 * kPoints);
  EXPECT_NEAR(SampleSpread(rms), theory, 0.05 * theory);
  EXPECT_NEAR(se_sum / kExperiments, SampleSpread(rms), 0.05 * SampleSpread(rms));
  EXPECT_NEAR(gain_se_sum / kExperiments, SampleSpread(gains), 0.05 * SampleSpread(gains));
  // Pairing removes what the points share: the gain is known better than the two RMS's own
  // errors, taken as independent, would say.
  EXPECT_LT(gain_se_sum, 0.7 * std::hypot(se_sum, after_se_sum));

  EXPECT_TRUE(std::isnan(RmsWithStandardError({}).rms));
  EXPECT_TRUE(std::isinf(RmsWithStandardError({4.0}).standard_error));
  EXPECT_DOUBLE_EQ(RmsWithStandardError({4.0}).rms, 2.0);
  EXPECT_THROW(RmsDifferenceStandardError({1.0, 2.0}, {1.0}), std::invalid_argument);
}

// Errors in groups that move together (a pose seen by three cameras shares the pose's own
// error): the grouped standard errors match the Monte Carlo spread where the ungrouped ones,
// taking every error as its own draw, claim too much. With every error its own group, the two
// forms are one.
TEST(Statistics, GroupedRmsStandardErrorsMatchTheirMonteCarloSpread) {
  constexpr int kExperiments = 4000;
  constexpr int kPoses = 40;
  constexpr int kRowsPerPose = 3;
  std::mt19937 rng(11);
  std::normal_distribution<double> pose_error(0.0, 0.08), row_noise(0.0, 0.03);
  std::vector<int> group;
  for (int p = 0; p < kPoses; ++p) group.insert(group.end(), kRowsPerPose, p);
  std::vector<double> rms, gains;
  double grouped_se = 0.0, ungrouped_se = 0.0, grouped_gain_se = 0.0;
  for (int e = 0; e < kExperiments; ++e) {
    std::vector<double> before, after;
    for (int p = 0; p < kPoses; ++p) {
      double shared[3], removed[3];
      for (int axis = 0; axis < 3; ++axis) {
        shared[axis] = pose_error(rng);
        removed[axis] = 0.5 * pose_error(rng);
      }
      for (int r = 0; r < kRowsPerPose; ++r) {
        double b2 = 0.0, a2 = 0.0;
        for (int axis = 0; axis < 3; ++axis) {
          const double kept = shared[axis] + row_noise(rng);
          b2 += (kept + removed[axis]) * (kept + removed[axis]);
          a2 += kept * kept;
        }
        before.push_back(b2);
        after.push_back(a2);
      }
    }
    const RmsEstimate grouped = RmsWithStandardError(before, group);
    rms.push_back(grouped.rms);
    grouped_se += grouped.standard_error;
    ungrouped_se += RmsWithStandardError(before).standard_error;
    gains.push_back(grouped.rms - std::sqrt(std::accumulate(after.begin(), after.end(), 0.0) /
                                            static_cast<double>(after.size())));
    grouped_gain_se += RmsDifferenceStandardError(before, after, group);
  }
  EXPECT_NEAR(grouped_se / kExperiments, SampleSpread(rms), 0.07 * SampleSpread(rms));
  EXPECT_NEAR(grouped_gain_se / kExperiments, SampleSpread(gains), 0.07 * SampleSpread(gains));
  EXPECT_LT(ungrouped_se / kExperiments, 0.8 * SampleSpread(rms));

  const std::vector<double> a = {1.0, 4.0, 2.5, 0.3}, b = {0.5, 3.0, 2.0, 0.1};
  EXPECT_DOUBLE_EQ(RmsWithStandardError(a, {7, 3, 9, 1}).standard_error,
                   RmsWithStandardError(a).standard_error);
  EXPECT_DOUBLE_EQ(RmsDifferenceStandardError(a, b, {7, 3, 9, 1}),
                   RmsDifferenceStandardError(a, b));
  EXPECT_TRUE(std::isinf(RmsWithStandardError(a, {2, 2, 2, 2}).standard_error));
  EXPECT_THROW(RmsWithStandardError(a, {1, 2}), std::invalid_argument);
  EXPECT_THROW(RmsDifferenceStandardError(a, b, {1}), std::invalid_argument);
}

TEST(Text, JoinAndMillimetres) {
  EXPECT_EQ(Join({"x", "y", "z"}), "x, y, z");
  EXPECT_EQ(Join({"a", "b"}, " / "), "a / b");
  EXPECT_EQ(Join({}), "");
  EXPECT_EQ(Mm(12.3456), "12.3 mm");
  EXPECT_EQ(Mm(12.3456, 4), "12.35 mm");
  EXPECT_EQ(Mm(0.00012), "0.00012 mm");
}

// RFC 3629's well-formed sequences: a lone continuation byte, an overlong form, a surrogate and
// a character cut short at the end are not UTF-8; two- to four-byte characters are.
TEST(Text, FirstInvalidUtf8ByteIsWhereWellFormedUtf8Stops) {
  EXPECT_EQ(FirstInvalidUtf8Byte("ok \x80"), 3u);
  EXPECT_EQ(FirstInvalidUtf8Byte("\xC0\xAF"), 0u);
  EXPECT_EQ(FirstInvalidUtf8Byte("a\xED\xA0\x80"), 1u);
  EXPECT_EQ(FirstInvalidUtf8Byte("end \xC5"), 4u);
  EXPECT_EQ(FirstInvalidUtf8Byte("end \xE2\x82"), 4u);
  EXPECT_FALSE(FirstInvalidUtf8Byte("°µ€ 😀"));
  EXPECT_FALSE(FirstInvalidUtf8Byte(""));
}

}  // namespace
}  // namespace cellmetry
