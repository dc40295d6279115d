// The blurred-step edge profile (edge_profile.h): Acklam's inverse normal CDF, the blur width
// fitted over a dot's crossings, and each crossing's weighted position and variance.
#include "dot_common/edge_profile.h"

#include <algorithm>
#include <cmath>

namespace cellmetry::dot {

double InverseNormalCdf(double p) {
  // P. J. Acklam, "An algorithm for computing the inverse normal cumulative distribution
  // function" (2003): rational approximations in the centre and the tails.
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  constexpr double low = 0.02425;
  if (p < low) {
    const double q = std::sqrt(-2.0 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  if (p > 1.0 - low) return -InverseNormalCdf(1.0 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

double FitEdgeWidth(const std::vector<Crossing>& crossings, double fallback) {
  // With e eliminated per crossing (weighted means), t - t_bar = -s k (u - u_bar) for every
  // sample (k the crossing's stretch): one-parameter weighted least squares in s.
  double num = 0.0, den = 0.0;
  for (const Crossing& c : crossings) {
    if (c.count < 2) continue;
    double sw = 0.0, st = 0.0, su = 0.0;
    for (int k = 0; k < c.count; ++k) sw += c.w[k], st += c.w[k] * c.t[k], su += c.w[k] * c.u[k];
    const double tb = st / sw, ub = su / sw;
    for (int k = 0; k < c.count; ++k) {
      const double du = c.stretch * (c.u[k] - ub);
      num -= c.w[k] * du * (c.t[k] - tb);
      den += c.w[k] * du * du;
    }
  }
  if (!(den > 0.0)) return fallback;
  const double s = num / den;
  return s > 0.2 && s < 10.0 ? s : fallback;
}

void RefineCrossing(const Crossing& c, double width, double sigma, double contrast, double* t,
                    double* variance) {
  const double s = width * c.stretch;
  double sw = 0.0, se = 0.0;
  for (int k = 0; k < c.count; ++k) sw += c.w[k], se += c.w[k] * (c.t[k] + s * c.u[k]);
  if (!(sw > 0.0)) {
    *t = c.linear_t;
    *variance = c.linear_variance;
    return;
  }
  *t = se / sw;
  // With w_k = exp(-u_k^2) = 2 pi phi(u_k)^2, d(position) / d(level_k) = s w_k / (contrast
  // phi(u_k) sum w), so the variance collapses to 2 pi s^2 sigma^2 / (contrast^2 sum w) (the
  // weights held fixed).
  *variance = 2.0 * M_PI * s * s * sigma * sigma / (contrast * contrast * sw);
}

}  // namespace cellmetry::dot
