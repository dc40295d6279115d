// Chi-square and normal tails, Durbin-Watson, Holm, medians, RMS errors and correlations
// (statistics.h): Boost.Math's gamma_q for the chi-square tail, Lentz's continued fraction for its
// logarithm where Q underflows.
#include "cellmetry/basics/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>

#include <boost/math/distributions/students_t.hpp>
#include <boost/math/special_functions/gamma.hpp>

namespace cellmetry {
namespace {

// log Q(a, x) by Lentz's continued fraction (Numerical Recipes 6.2), for x >= a + 1 where Q
// underflows a double. Boost.Math gives Q itself but not its logarithm, which the physics finder
// needs to compare statistics of thousands of sigma with different degrees of freedom.
double LogUpperGammaFraction(double a, double x) {
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-15) break;
  }
  return -x + a * std::log(x) - std::lgamma(a) + std::log(h);
}

double MeanOf(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return sum / static_cast<double>(v.size());
}

// Sample standard deviation over sqrt(n) of v: the standard error of its mean.
double StandardErrorOfMean(const std::vector<double>& v) {
  if (v.size() < 2) return std::numeric_limits<double>::infinity();
  const double n = static_cast<double>(v.size());
  const double mean = MeanOf(v);
  double squares = 0.0;
  for (double x : v) squares += (x - mean) * (x - mean);
  return std::sqrt(squares / (n - 1.0) / n);
}

std::vector<int> EachItsOwnGroup(size_t count) {
  std::vector<int> group(count);
  std::iota(group.begin(), group.end(), 0);
  return group;
}

void CheckOnePerError(const char* function, size_t errors, size_t groups) {
  if (errors != groups) {
    throw std::invalid_argument(std::string(function) + ": " + std::to_string(groups) +
                                " groups for " + std::to_string(errors) + " errors");
  }
}

// Each group's linearised share of the mean square m = sum e^2 / n: (its sum of e^2 - m times
// its count) over the mean group size, in the order the groups first appear. Their mean is 0;
// their variance over their count is the mean square's.
std::vector<double> GroupShares(const std::vector<double>& squared, const std::vector<int>& group,
                                double mean_square) {
  std::map<int, size_t> index_of;
  std::vector<double> sums;
  std::vector<double> counts;
  for (size_t i = 0; i < squared.size(); ++i) {
    const auto [it, added] = index_of.emplace(group[i], sums.size());
    if (added) {
      sums.push_back(0.0);
      counts.push_back(0.0);
    }
    sums[it->second] += squared[i];
    counts[it->second] += 1.0;
  }
  const double mean_size = static_cast<double>(squared.size()) / static_cast<double>(sums.size());
  std::vector<double> shares(sums.size());
  for (size_t g = 0; g < sums.size(); ++g) {
    shares[g] = (sums[g] - mean_square * counts[g]) / mean_size;
  }
  return shares;
}

}  // namespace

double ChiSquareSurvival(double x, double k) {
  if (!(x > 0)) return 1.0;
  return boost::math::gamma_q(0.5 * k, 0.5 * x);
}

double ChiSquareLogSurvival(double x, double k) {
  if (!(x > 0)) return 0.0;
  const double q = boost::math::gamma_q(0.5 * k, 0.5 * x);
  if (q > 1e-250) return std::log(q);
  return LogUpperGammaFraction(0.5 * k, 0.5 * x);
}

double ChiSquareQuantile(double p, double k) { return 2.0 * boost::math::gamma_p_inv(0.5 * k, p); }

double NormalSurvival(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

double DurbinWatson(const std::vector<double>& e) {
  double num = 0.0, den = 0.0;
  for (size_t t = 0; t < e.size(); ++t) {
    den += e[t] * e[t];
    if (t > 0) num += (e[t] - e[t - 1]) * (e[t] - e[t - 1]);
  }
  return den > 0 ? num / den : 2.0;
}

std::vector<double> HolmAdjusted(const std::vector<double>& p) {
  const size_t m = p.size();
  std::vector<size_t> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return p[a] < p[b]; });
  std::vector<double> adjusted(m);
  double running = 0.0;
  for (size_t rank = 0; rank < m; ++rank) {
    running = std::max(running, std::min(1.0, (m - rank) * p[order[rank]]));
    adjusted[order[rank]] = running;
  }
  return adjusted;
}

double Median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  if (values.size() % 2) return values[mid];
  const double upper = values[mid];
  return 0.5 * (*std::max_element(values.begin(), values.begin() + mid) + upper);
}

double UpperMedian(std::vector<double>* values) {
  if (values->empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t mid = values->size() / 2;
  std::nth_element(values->begin(), values->begin() + mid, values->end());
  return (*values)[mid];
}

MeanInterval TInterval95(const std::vector<double>& values) {
  MeanInterval m;
  m.n = static_cast<int>(values.size());
  if (m.n == 0) {
    m.mean = m.low = m.high = std::numeric_limits<double>::quiet_NaN();
    return m;
  }
  m.mean = MeanOf(values);
  if (m.n < 2) {
    m.low = -std::numeric_limits<double>::infinity();
    m.high = std::numeric_limits<double>::infinity();
    return m;
  }
  const double t = boost::math::quantile(boost::math::students_t(m.n - 1), 0.975);
  const double se = StandardErrorOfMean(values);
  m.low = m.mean - t * se;
  m.high = m.mean + t * se;
  return m;
}

RmsEstimate RmsWithStandardError(const std::vector<double>& squared_errors) {
  return RmsWithStandardError(squared_errors, EachItsOwnGroup(squared_errors.size()));
}

RmsEstimate RmsWithStandardError(const std::vector<double>& squared_errors,
                                 const std::vector<int>& group) {
  CheckOnePerError("RmsWithStandardError", squared_errors.size(), group.size());
  if (squared_errors.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan};
  }
  RmsEstimate e;
  const double mean_square = MeanOf(squared_errors);
  e.rms = std::sqrt(mean_square);
  // d sqrt(m) / dm = 1 / (2 sqrt(m)), times the standard error of the mean square m.
  e.standard_error =
      e.rms > 0.0
          ? StandardErrorOfMean(GroupShares(squared_errors, group, mean_square)) / (2.0 * e.rms)
          : std::numeric_limits<double>::infinity();
  return e;
}

double RmsDifferenceStandardError(const std::vector<double>& before_squared,
                                  const std::vector<double>& after_squared) {
  return RmsDifferenceStandardError(before_squared, after_squared,
                                    EachItsOwnGroup(before_squared.size()));
}

double RmsDifferenceStandardError(const std::vector<double>& before_squared,
                                  const std::vector<double>& after_squared,
                                  const std::vector<int>& group) {
  if (before_squared.size() != after_squared.size()) {
    throw std::invalid_argument(
        "RmsDifferenceStandardError: " + std::to_string(before_squared.size()) +
        " points against " + std::to_string(after_squared.size()));
  }
  CheckOnePerError("RmsDifferenceStandardError", before_squared.size(), group.size());
  if (before_squared.size() < 2) return std::numeric_limits<double>::infinity();
  const double before_mean_square = MeanOf(before_squared);
  const double after_mean_square = MeanOf(after_squared);
  const double rms_before = std::sqrt(before_mean_square);
  const double rms_after = std::sqrt(after_mean_square);
  if (rms_before <= 0.0 || rms_after <= 0.0) return std::numeric_limits<double>::infinity();
  const std::vector<double> before = GroupShares(before_squared, group, before_mean_square);
  const std::vector<double> after = GroupShares(after_squared, group, after_mean_square);
  std::vector<double> paired(before.size());
  for (size_t g = 0; g < paired.size(); ++g) {
    paired[g] = before[g] / (2.0 * rms_before) - after[g] / (2.0 * rms_after);
  }
  return StandardErrorOfMean(paired);
}

Eigen::MatrixXd CorrelationOf(const Eigen::MatrixXd& covariance) {
  const Eigen::VectorXd sigma = covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  const Eigen::Index n = covariance.rows();
  Eigen::MatrixXd correlation(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const double d = sigma[i] * sigma[j];
      correlation(i, j) = d > 0 ? covariance(i, j) / d : (i == j ? 1.0 : 0.0);
    }
  }
  return correlation;
}

}  // namespace cellmetry
