// CorrelationHeatmap (plots.h): the free parameters' correlation matrix.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cellmetry/report/plots.h"

namespace cellmetry::report {
namespace {

// -1 blue, 0 white, +1 red.
std::string Diverging(double rho) {
  const double t = std::clamp(std::abs(rho), 0.0, 1.0);
  const int fade = static_cast<int>(255 * (1 - t));
  char buffer[16];
  if (rho >= 0) {
    std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", 200 + (55 * fade) / 255, fade, fade);
  } else {
    std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x", fade, fade, 200 + (55 * fade) / 255);
  }
  return buffer;
}

}  // namespace

std::string CorrelationHeatmap(const std::vector<std::string>& names,
                               const std::vector<std::vector<double>>& correlation) {
  const size_t n = names.size();
  size_t longest = 0;
  for (const auto& name : names) longest = std::max(longest, name.size());
  const double cell = n > 60 ? 5.0 : n > 25 ? 9.0 : 16.0;
  const double left = std::min(260.0, 12 + 6.2 * static_cast<double>(longest));
  SvgPlot plot("correlation_heatmap", left + cell * n + 14, 14 + cell * n + 42);
  plot.SetMarginLeft(left);
  plot.SetX({-0.5, static_cast<double>(n) - 0.5}, "parameter index (order as listed)");
  plot.SetYCategories(n <= 60 ? names : std::vector<std::string>(n), "");
  for (size_t i = 0; i < n && i < correlation.size(); ++i) {
    for (size_t k = 0; k < n && k < correlation[i].size(); ++k) {
      const double rho = correlation[i][k];
      if (!std::isfinite(rho) || (std::abs(rho) < 0.05 && i != k)) continue;
      plot.Rect(k - 0.5, i - 0.5, k + 0.5, i + 0.5, Diverging(rho), 1.0,
                names[i] + " ~ " + names[k] + ": " + Num(rho, 3));
    }
  }
  plot.Legend({{Diverging(-1), "-1"}, {Diverging(1), "+1"}});
  plot.Caption(std::to_string(n) +
               " free parameters; red: positive, blue: negative correlation; "
               "white: |rho| < 0.05. Hover a cell for its pair and value." +
               std::string(n > 60 ? " Names are listed in the sigma table (same order)." : ""));
  return plot.Svg();
}

}  // namespace cellmetry::report
