// ScatterPlot (plots.h): points, or a log-count density once there are more than kMaxMarks.
#include <algorithm>
#include <cmath>
#include <map>

#include "cellmetry/report/plots.h"

namespace cellmetry::report {
namespace {

// The y range: every value and reference line, or with `spec.fenced_y` the values within
// FencedRangeOf (each series a population) and the lines, the rest drawn at the edge; symmetric
// about 0 where asked.
Range YRange(const ScatterSpec& spec, const std::vector<double>& ys) {
  std::vector<double> held = ys;
  if (spec.fenced_y) {
    std::vector<std::vector<double>> populations;
    for (const auto& s : spec.series) populations.push_back(s.y);
    const Range fenced = FencedRangeOf(populations);
    held.erase(std::remove_if(held.begin(), held.end(),
                              [&](double v) { return v < fenced.lo || v > fenced.hi; }),
               held.end());
  }
  held.insert(held.end(), spec.hlines.begin(), spec.hlines.end());
  Range y = RangeOf(held, spec.symmetric_y);
  if (spec.symmetric_y) {
    const double m = std::max(std::abs(y.lo), std::abs(y.hi));
    y = {-m, m};
  }
  return y;
}

// One series as points: each in the axes a circle, each beyond them a mark at the edge.
void DrawPoints(const Series& s, const std::string& color, SvgPlot* plot) {
  const size_t n = std::min(s.x.size(), s.y.size());
  const double radius = n > 500 ? 1.6 : 2.4;
  for (size_t i = 0; i < n; ++i) {
    plot->Circle(s.x[i], s.y[i], radius, color, i < s.titles.size() ? s.titles[i] : "", 0.65);
  }
}

// One series as a density of kDensityColumns x kDensityRows cells; the points beyond the y range
// are one edge mark per column and side, standing for their count.
void DrawDensity(const Series& s, const std::string& color, Range x, Range y, SvgPlot* plot) {
  const double cw = (x.hi - x.lo) / kDensityColumns, ch = (y.hi - y.lo) / kDensityRows;
  std::map<std::pair<int, int>, int> counts, beyond;  // (column, row); (column, side)
  std::map<std::pair<int, int>, double> beyond_x;
  const size_t n = std::min(s.x.size(), s.y.size());
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
    const int c = std::clamp(static_cast<int>((s.x[i] - x.lo) / cw), 0, kDensityColumns - 1);
    if (s.y[i] < y.lo || s.y[i] > y.hi) {
      const std::pair<int, int> key{c, s.y[i] > y.hi ? 1 : -1};
      ++beyond[key];
      beyond_x[key] = s.x[i];
      continue;
    }
    const int r = std::clamp(static_cast<int>((s.y[i] - y.lo) / ch), 0, kDensityRows - 1);
    ++counts[{c, r}];
  }
  int most = 1;
  for (const auto& [cell, count] : counts) most = std::max(most, count);
  for (const auto& [cell, count] : counts) {
    const double x0 = x.lo + cell.first * cw, y0 = y.lo + cell.second * ch;
    const double opacity = 0.3 + 0.7 * std::log1p(count) / std::log1p(most);
    plot->Rect(x0, y0, x0 + cw, y0 + ch, color, opacity);  // no title: size
  }
  for (const auto& [key, count] : beyond) {
    const double edge = key.second > 0 ? y.hi + 1 : y.lo - 1;  // any value past the edge
    plot->BeyondMark(std::clamp(beyond_x[key], x.lo, x.hi), edge, color,
                     s.name + ": " + std::to_string(count), count);
  }
}

}  // namespace

std::string ScatterPlot(const ScatterSpec& spec) {
  std::vector<double> xs, ys;
  size_t total = 0;
  for (const auto& s : spec.series) {
    xs.insert(xs.end(), s.x.begin(), s.x.end());
    ys.insert(ys.end(), s.y.begin(), s.y.end());
    total += std::min(s.x.size(), s.y.size());
  }
  std::vector<std::pair<std::string, std::string>> legend;
  for (size_t k = 0; spec.series.size() > 1 && k < spec.series.size(); ++k) {
    legend.push_back({SeriesColor(static_cast<int>(k)), spec.series[k].name});
  }
  // The legend takes its room from the data area: scatters sit three in a row.
  SvgPlot plot(spec.kind, spec.width - SvgPlot::LegendWidth(legend), spec.height);
  const Range x = RangeOf(xs), y = YRange(spec, ys);
  plot.SetX(x, spec.x_label);
  plot.SetY(y, spec.y_label);
  for (double h : spec.hlines) plot.HLine(h, "#c33");
  const bool binned = total > static_cast<size_t>(kMaxMarks);
  for (size_t k = 0; k < spec.series.size(); ++k) {
    const std::string color = SeriesColor(static_cast<int>(k));
    if (binned) {
      DrawDensity(spec.series[k], color, x, y, &plot);
    } else {
      DrawPoints(spec.series[k], color, &plot);
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
