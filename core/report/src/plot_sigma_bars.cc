// SigmaBars (plots.h): sigma per parameter, split into its parts by share of the variance.
#include <algorithm>
#include <cmath>

#include "cellmetry/report/plots.h"

namespace cellmetry::report {

std::string SigmaBars(const std::vector<SigmaEntry>& entries, const std::string& unit) {
  std::vector<std::string> names;
  double top = 0.0;
  size_t longest = 0;
  for (const auto& e : entries) {
    names.push_back(e.name);
    longest = std::max(longest, e.name.size());
    if (std::isfinite(e.total)) top = std::max(top, e.total);
  }
  const double height = 50 + 15.0 * static_cast<double>(entries.size());
  SvgPlot plot("sigma_bars", 520, height);
  plot.SetMarginLeft(std::min(260.0, 12 + 6.2 * static_cast<double>(longest)));
  plot.SetX({0, top > 0 ? 1.05 * top : 1.0}, "sigma (" + unit + ")");
  plot.SetYCategories(names, "");
  bool parts = false;
  for (size_t i = 0; i < entries.size(); ++i) {
    const SigmaEntry& e = entries[i];
    const double y0 = static_cast<double>(i) - 0.36, y1 = static_cast<double>(i) + 0.36;
    const double total2 = e.total * e.total;
    const double split =
        e.statistical * e.statistical + e.systematic * e.systematic + e.inputs * e.inputs;
    const std::string title = e.name + ": " + Num(e.total, 3) + " " + unit + " (statistical " +
                              Num(e.statistical, 3) + ", systematic " + Num(e.systematic, 3) +
                              ", inputs " + Num(e.inputs, 3) + ")";
    if (!(total2 > 0) || !(split > 0)) {
      plot.Rect(0, y0, e.total, y1, "#888", 1.0, e.name + ": " + Num(e.total, 3) + " " + unit);
      continue;
    }
    parts = true;
    double at = 0.0;
    const double shares[3] = {e.statistical * e.statistical, e.systematic * e.systematic,
                              e.inputs * e.inputs};
    for (int k = 0; k < 3; ++k) {
      const double length = e.total * shares[k] / split;
      if (length <= 0) continue;
      plot.Rect(at, y0, at + length, y1, SeriesColor(k), 1.0, title);
      at += length;
    }
  }
  if (parts) {
    plot.Legend({{SeriesColor(0), "statistical"},
                 {SeriesColor(1), "systematic"},
                 {SeriesColor(2), "inputs"}});
    plot.Caption(
        "Bar length: total sigma. Segments: each part's share of the variance "
        "(sigma^2 = statistical^2 + systematic^2 + inputs^2). Grey: no parts computed.");
  }
  return plot.Svg();
}

}  // namespace cellmetry::report
