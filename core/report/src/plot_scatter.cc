// ScatterPlot (plots.h): points, or a log-count density once there are more than kMaxMarks.
#include <algorithm>
#include <cmath>
#include <map>

#include "cellmetry/report/plots.h"

namespace cellmetry::report {

std::string ScatterPlot(const ScatterSpec& spec) {
  std::vector<double> xs, ys;
  size_t total = 0;
  for (const auto& s : spec.series) {
    xs.insert(xs.end(), s.x.begin(), s.x.end());
    ys.insert(ys.end(), s.y.begin(), s.y.end());
    total += std::min(s.x.size(), s.y.size());
  }
  ys.insert(ys.end(), spec.hlines.begin(), spec.hlines.end());
  SvgPlot plot(spec.kind, spec.width, spec.height);
  const Range x = RangeOf(xs);
  Range y = RangeOf(ys, spec.symmetric_y);
  if (spec.symmetric_y) {
    const double m = std::max(std::abs(y.lo), std::abs(y.hi));
    y = {-m, m};
  }
  plot.SetX(x, spec.x_label);
  plot.SetY(y, spec.y_label);
  for (double h : spec.hlines) plot.HLine(h, "#c33");
  std::vector<std::pair<std::string, std::string>> legend;
  const bool binned = total > static_cast<size_t>(kMaxMarks);
  for (size_t k = 0; k < spec.series.size(); ++k) {
    const Series& s = spec.series[k];
    const std::string color = SeriesColor(static_cast<int>(k));
    if (spec.series.size() > 1) legend.push_back({color, s.name});
    const size_t n = std::min(s.x.size(), s.y.size());
    if (!binned) {
      const double radius = n > 500 ? 1.6 : 2.4;
      for (size_t i = 0; i < n; ++i) {
        plot.Circle(s.x[i], s.y[i], radius, color, i < s.titles.size() ? s.titles[i] : "", 0.65);
      }
      continue;
    }
    const double cw = (x.hi - x.lo) / kDensityColumns, ch = (y.hi - y.lo) / kDensityRows;
    std::map<std::pair<int, int>, int> counts;
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      const int c = std::clamp(static_cast<int>((s.x[i] - x.lo) / cw), 0, kDensityColumns - 1);
      const int r = std::clamp(static_cast<int>((s.y[i] - y.lo) / ch), 0, kDensityRows - 1);
      ++counts[{c, r}];
    }
    int most = 1;
    for (const auto& [cell, count] : counts) most = std::max(most, count);
    for (const auto& [cell, count] : counts) {
      const double x0 = x.lo + cell.first * cw, y0 = y.lo + cell.second * ch;
      const double opacity = 0.3 + 0.7 * std::log1p(count) / std::log1p(most);
      plot.Rect(x0, y0, x0 + cw, y0 + ch, color, opacity);  // no title: size
    }
  }
  plot.Legend(legend);
  std::string caption = spec.caption;
  if (binned) {
    caption += (caption.empty() ? "" : " ") + std::to_string(total) + " points drawn as a " +
               std::to_string(kDensityColumns) + " x " + std::to_string(kDensityRows) +
               " density per series (shade: log of the count).";
  }
  plot.Caption(caption);
  return plot.Svg();
}

}  // namespace cellmetry::report
