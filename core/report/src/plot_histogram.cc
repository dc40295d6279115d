// NormalHistogram (plots.h): whitened residuals against the N(0,1) density.
#include <algorithm>
#include <cmath>

#include "cellmetry/report/plots.h"

namespace cellmetry::report {

std::string NormalHistogram(const std::vector<double>& whitened, const std::string& label,
                            const std::string& kind) {
  constexpr double kEdge = 6.0;
  constexpr int kBins = 48;
  const double width = 2 * kEdge / kBins;
  std::vector<int> counts(kBins, 0);
  int n = 0, beyond3 = 0, below_edge = 0, above_edge = 0;
  double sum = 0, sum2 = 0;
  for (double v : whitened) {
    if (!std::isfinite(v)) continue;
    ++n;
    sum += v;
    sum2 += v * v;
    if (std::abs(v) > 3) ++beyond3;
    if (v < -kEdge || v > kEdge) {
      ++(v < 0 ? below_edge : above_edge);
      continue;  // not in a bin: a mark at the edge stands for it
    }
    ++counts[std::clamp(static_cast<int>((v + kEdge) / width), 0, kBins - 1)];
  }
  std::vector<double> density(kBins, 0.0);
  double top = 1.0 / std::sqrt(2 * M_PI);
  for (int b = 0; b < kBins; ++b) {
    density[b] = n > 0 ? counts[b] / (n * width) : 0.0;
    top = std::max(top, density[b]);
  }
  SvgPlot plot(kind, 380, 240);
  plot.SetX({-kEdge, kEdge}, label);
  plot.SetY({0, 1.08 * top}, "density");
  for (int b = 0; b < kBins; ++b) {
    if (counts[b] == 0) continue;
    const double x0 = -kEdge + b * width;
    plot.Rect(x0, 0, x0 + width, density[b], "#7a9cc6", 0.85,
              std::to_string(counts[b]) + " in [" + Num(x0, 3) + ", " + Num(x0 + width, 3) + ")");
  }
  std::vector<double> gx, gy;
  for (double x = -kEdge; x <= kEdge + 1e-9; x += 0.1) {
    gx.push_back(x);
    gy.push_back(std::exp(-0.5 * x * x) / std::sqrt(2 * M_PI));
  }
  plot.Polyline(gx, gy, "#c33", 1.8);
  plot.BeyondMark(-2 * kEdge, 0, "#7a9cc6", std::to_string(below_edge) + " below -6", below_edge);
  plot.BeyondMark(2 * kEdge, 0, "#7a9cc6", std::to_string(above_edge) + " above 6", above_edge);
  plot.Legend({{"#7a9cc6", "residuals"}, {"#c33", "N(0,1)"}});
  const double mean = n > 0 ? sum / n : 0.0;
  const double sd = n > 1 ? std::sqrt(std::max(0.0, (sum2 - n * mean * mean) / (n - 1))) : 0.0;
  plot.Caption(std::to_string(n) + " values: mean " + Num(mean, 3) + ", sd " + Num(sd, 3) + "; " +
               Num(n > 0 ? 100.0 * beyond3 / n : 0.0, 3) + " % beyond 3 (N(0,1): 0.27 %).");
  return plot.Svg();
}

}  // namespace cellmetry::report
