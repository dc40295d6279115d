// 95 % intervals, the decisions drawn from them, and how the tables write them (intervals.h).
#include "cellmetry/experiments/intervals.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace cellmetry {

bool Overlap(const MeanInterval& a, const MeanInterval& b) {
  return !(a.high < b.low || b.high < a.low);
}

bool SameScore(const std::vector<double>& a, const std::vector<double>& b, double resolution) {
  const MeanInterval ma = TInterval95(a), mb = TInterval95(b);
  if (std::abs(ma.mean - mb.mean) <=
      std::max(resolution, 0.01 * std::max(std::abs(ma.mean), std::abs(mb.mean)))) {
    return true;  // within 1 % or the resolution: no difference worth a decision
  }
  if (a.size() == b.size() && a.size() >= 2) {
    std::vector<double> difference(a.size());
    for (size_t i = 0; i < a.size(); ++i) difference[i] = a[i] - b[i];
    const MeanInterval d = TInterval95(difference);
    return d.low <= 0.0 && 0.0 <= d.high;
  }
  return Overlap(ma, mb);
}

namespace {
constexpr double kZ95 = 1.959963984540054;  // the standard normal's 0.975 quantile

// The score interval of a rate p observed over n runs (n > 0).
void WilsonBounds(double p, int n, double* low, double* high) {
  const double z2 = kZ95 * kZ95;
  const double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  const double half = kZ95 / (1.0 + z2 / n) * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n));
  *low = std::max(0.0, centre - half);
  *high = std::min(1.0, centre + half);
}

}  // namespace

RateInterval WilsonInterval95(int k, int n) {
  RateInterval r;
  r.k = k;
  r.n = n;
  if (n <= 0) {
    r.rate = std::numeric_limits<double>::quiet_NaN();
    return r;  // [0, 1]: nothing known
  }
  r.rate = static_cast<double>(k) / n;
  WilsonBounds(r.rate, n, &r.low, &r.high);
  return r;
}

TargetVerdict AgainstTarget(const RateInterval& r, double target) {
  if (r.n <= 0) return TargetVerdict::kUndecided;
  if (r.low >= target) return TargetVerdict::kMet;
  if (r.high < target) return TargetVerdict::kMissed;
  return TargetVerdict::kUndecided;
}

int RunsToShowAtLeast(double target) {
  // With k = n the Wilson low end is n / (n + z^2): it clears `target` from n = z^2 t / (1 - t).
  return static_cast<int>(std::ceil(kZ95 * kZ95 * target / (1.0 - target) - 1e-9));
}

int RunsToDecide(double rate, double target, int runs_so_far) {
  for (int n = std::max(1, runs_so_far + 1); n <= 1000000; n += std::max(1, n / 64)) {
    double low = 0.0, high = 1.0;
    WilsonBounds(rate, n, &low, &high);
    if (low >= target || high < target) return n;
  }
  return -1;
}

std::string RateText(const RateInterval& r) {
  if (r.n <= 0) return "-";
  char text[96];
  std::snprintf(text, sizeof text, "%.0f %% [%.0f %%, %.0f %%] (%d/%d)", 100.0 * r.rate,
                100.0 * r.low, 100.0 * r.high, r.k, r.n);
  return text;
}

std::string FigureText(double value, FigureStyle style) {
  const bool small = value != 0.0 && std::abs(value) < 1e-3;
  char text[48];
  switch (style) {
    case FigureStyle::kThreeDigits:
      std::snprintf(text, sizeof text, small ? "%.2e" : "%.3g", value);
      break;
    case FigureStyle::kFourDecimals:
      std::snprintf(text, sizeof text, small ? "%.1e" : "%.4f", value);
      break;
    case FigureStyle::kFourDigits: std::snprintf(text, sizeof text, "%.4g", value); break;
  }
  return text;
}

std::string IntervalText(const MeanInterval& m, double scale, FigureStyle style) {
  return FigureText(m.mean * scale, style) + " [" + FigureText(m.low * scale, style) + ", " +
         FigureText(m.high * scale, style) + "]";
}

std::string IntervalText(const std::vector<double>& values, double scale, FigureStyle style) {
  if (values.empty()) return "-";
  return IntervalText(TInterval95(values), scale, style);
}

}  // namespace cellmetry
