// Small statistics the physics finder and the comparisons need: tail probabilities of the
// chi-square and normal distributions, the Durbin-Watson statistic, the Holm correction,
// medians, a mean's 95 % Student-t interval, an RMS's standard error, and a covariance's
// correlation matrix.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace cellmetry {

// P(X > x) for X ~ chi-square with k degrees of freedom: the regularized upper incomplete gamma
// Q(k/2, x/2) of Boost.Math.
double ChiSquareSurvival(double x, double k);

// log P(X > x), accurate where P itself underflows (x in the thousands): compares statistics of
// different degrees of freedom however strong they are. Boost.Math's Q where it is a normal
// double; below 1e-250, log Q from Lentz's continued fraction (Boost.Math has no log Q).
double ChiSquareLogSurvival(double x, double k);

// x with P(X <= x) = p for X ~ chi-square with k degrees of freedom (Boost.Math).
double ChiSquareQuantile(double p, double k);

// P(Z > z) for a standard normal Z.
double NormalSurvival(double z);

// sum (e_t - e_{t-1})^2 / sum e_t^2 over a sequence in capture order: about 2 when neighbours
// are independent, towards 0 when errors drift slowly (Durbin & Watson 1950).
double DurbinWatson(const std::vector<double>& residuals);

// Holm's step-down adjusted p-values (Holm 1979): the family-wise error rate stays at alpha when
// each hypothesis is rejected at adjusted p < alpha. Same order as `p`.
std::vector<double> HolmAdjusted(const std::vector<double>& p);

// The median: the middle value, or the mean of the two middle values of an even count; NaN for
// no values.
double Median(std::vector<double> values);

// The upper of the two middle values of an even count (the middle value of an odd one), found
// in place: `values` is reordered, not copied, for the hot paths that reuse one scratch vector.
// NaN for no values.
double UpperMedian(std::vector<double>* values);

// A mean and its two-sided 95 % Student-t interval, mean +- t(0.975, n-1) s / sqrt(n); with
// fewer than two values the interval is unbounded (nothing can be told apart).
struct MeanInterval {
  double mean = 0.0;
  double low = 0.0;
  double high = 0.0;
  int n = 0;
};
MeanInterval TInterval95(const std::vector<double>& values);

// The root mean square of n errors given as their squares e_i^2, and its standard error with the
// errors as independent draws: by the delta method, sd(e^2) / (2 RMS sqrt(n)) (Casella & Berger,
// Statistical Inference, 2nd ed., theorem 5.5.24), with sd the sample standard deviation. For
// 3D errors N(0, s^2 I) it is s / sqrt(2 n). NaN for no errors; the standard error is unbounded
// for one error or an RMS of 0.
struct RmsEstimate {
  double rms = 0.0;
  double standard_error = 0.0;
};
RmsEstimate RmsWithStandardError(const std::vector<double>& squared_errors);

// The same with the errors in groups that move together (a pose's rows: its cameras, its
// repeated captures, all sharing the pose's own error): `group[i]` is error i's group, and the
// groups, not the errors, are the independent draws. The mean square is then the ratio
// sum e^2 / n over groups, its variance by linearising it about its value: the groups'
// sum e^2 - RMS^2 n, over the mean group size, have that variance over their count (Cochran,
// Sampling Techniques, 3rd ed., section 6.4, the ratio estimate). With every error its own
// group, the ungrouped standard error. Unbounded for fewer than two groups; throws
// std::invalid_argument when `group` is not one per error.
RmsEstimate RmsWithStandardError(const std::vector<double>& squared_errors,
                                 const std::vector<int>& group);

// The same n points scored by two models, squares `before` and `after` in the same order: the
// standard error of RMS_before - RMS_after, by the delta method on the paired differences
// e_before^2 / (2 RMS_before) - e_after^2 / (2 RMS_after). Pairing removes what the points share
// (a hard pose is hard for both), so a gain can be far beyond its error when each RMS's own
// error is not. Unbounded for fewer than two points; throws std::invalid_argument when the two
// counts differ.
double RmsDifferenceStandardError(const std::vector<double>& before_squared,
                                  const std::vector<double>& after_squared);

// The same with the points in groups, as RmsWithStandardError above: each group's linearised
// share of RMS_before minus its share of RMS_after, over the groups.
double RmsDifferenceStandardError(const std::vector<double>& before_squared,
                                  const std::vector<double>& after_squared,
                                  const std::vector<int>& group);

// The correlation matrix of a covariance: C(i, j) / (sigma_i sigma_j) with sigma the square
// roots of the diagonal (negative round-off taken as 0). An entry without spread (sigma 0) is
// uncorrelated with the others and fully with itself: 0 off the diagonal, 1 on it.
Eigen::MatrixXd CorrelationOf(const Eigen::MatrixXd& covariance);

}  // namespace cellmetry
