// Chi-square and normal tails, Durbin-Watson, Holm, medians, RMS errors and correlations
// (statistics.h): Boost.Math's gamma_q for the chi-square tail, Lentz's continued fraction for its
// logarithm where Q underflows.
#include "cellmetry/basics/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
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
  if (squared_errors.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan};
  }
  RmsEstimate e;
  e.rms = std::sqrt(MeanOf(squared_errors));
  // d sqrt(m) / dm = 1 / (2 sqrt(m)), times the standard error of the mean square m.
  e.standard_error = e.rms > 0.0 ? StandardErrorOfMean(squared_errors) / (2.0 * e.rms)
                                 : std::numeric_limits<double>::infinity();
  return e;
}

double RmsDifferenceStandardError(const std::vector<double>& before_squared,
                                  const std::vector<double>& after_squared) {
  if (before_squared.size() != after_squared.size()) {
    throw std::invalid_argument(
        "RmsDifferenceStandardError: " + std::to_string(before_squared.size()) +
        " points against " + std::to_string(after_squared.size()));
  }
  if (before_squared.size() < 2) return std::numeric_limits<double>::infinity();
  const double rms_before = std::sqrt(MeanOf(before_squared));
  const double rms_after = std::sqrt(MeanOf(after_squared));
  if (rms_before <= 0.0 || rms_after <= 0.0) return std::numeric_limits<double>::infinity();
  std::vector<double> paired(before_squared.size());
  for (size_t i = 0; i < paired.size(); ++i) {
    paired[i] = before_squared[i] / (2.0 * rms_before) - after_squared[i] / (2.0 * rms_after);
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
