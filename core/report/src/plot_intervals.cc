// IntervalPlot (plots.h): a value with its interval per row.
#include <algorithm>
#include <cmath>

#include "cellmetry/report/plots.h"

namespace cellmetry::report {

std::string IntervalPlot(const std::string& kind, const std::vector<IntervalRow>& rows,
                         const std::string& x_label, const std::string& caption,
                         const std::vector<std::pair<std::string, std::string>>& legend,
                         const std::vector<double>& vlines) {
  std::vector<std::string> labels;
  std::vector<double> xs(vlines);
  size_t longest = 0;
  for (const auto& r : rows) {
    labels.push_back(r.label);
    longest = std::max(longest, r.label.size());
    xs.insert(xs.end(), {r.value, r.lo, r.hi});
  }
  SvgPlot plot(kind, 560, 50 + 17.0 * static_cast<double>(rows.size()));
  plot.SetMarginLeft(std::min(300.0, 12 + 6.2 * static_cast<double>(longest)));
  plot.SetX(RangeOf(xs), x_label);
  plot.SetYCategories(labels, "");
  for (double v : vlines) plot.VLine(v, "#c33");
  for (size_t i = 0; i < rows.size(); ++i) {
    const IntervalRow& r = rows[i];
    const std::string color = SeriesColor(r.color);
    const double y = static_cast<double>(i);
    const std::string title = r.label + ": " + Num(r.value, 4) +
                              (r.lo != r.hi ? " [" + Num(r.lo, 4) + ", " + Num(r.hi, 4) + "]" : "");
    if (r.lo != r.hi) plot.Rect(r.lo, y - 0.12, r.hi, y + 0.12, color, 0.45, title);
    plot.Circle(r.value, y, 3.2, color, title, 1.0);
  }
  plot.Legend(legend);
  plot.Caption(caption);
  return plot.Svg();
}

}  // namespace cellmetry::report
