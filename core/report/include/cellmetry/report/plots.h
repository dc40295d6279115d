// The plot kinds a report is made of, each a function from numbers to SvgPlot markup
// (svg_plot.h), each in its own source file (plot_<kind>.cc).
//
// Size contract: no plot draws more than about kMaxMarks marks whatever its input. A scatter
// with more points is drawn as a density: the box is cut into kDensityColumns x kDensityRows
// cells per series and every occupied cell is one rectangle whose opacity grows with the log of
// its count, so single points (an outlier, a gap in capture order) stay visible and 80,000 rows
// cost the same few kilobytes as 2,000. The caption says when a plot was binned.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/report/svg_plot.h"

namespace cellmetry::report {

inline constexpr int kMaxMarks = 2000;
inline constexpr int kDensityColumns = 60;
inline constexpr int kDensityRows = 30;

struct Series {
  std::string name;
  std::vector<double> x, y;
  std::vector<std::string> titles;  // optional hover text per point (ignored when binned)
};

struct ScatterSpec {
  std::string kind;  // data-plot attribute: "residual_order", ...
  std::string x_label, y_label;
  std::vector<Series> series;
  std::string caption;
  std::vector<double> hlines;  // dashed reference lines (a threshold, +-3 sigma)
  bool symmetric_y = false;    // y range symmetric about 0 (residuals)
  // y range from FencedRangeOf (each series a population), so that a few gross values do not
  // squash the band; those beyond are drawn at the edge and counted in the caption.
  bool fenced_y = false;
  double width = 380, height = 240;
};
std::string ScatterPlot(const ScatterSpec& spec);  // plot_scatter.cc

// Histogram of whitened residuals on [-6, 6] as a density, with the N(0,1) density drawn over
// it. Values beyond +-6 are left out of the bins and drawn as one mark at each edge they lie
// beyond, counted in the caption.
std::string NormalHistogram(const std::vector<double>& whitened, const std::string& label,
                            const std::string& kind = "whitened_histogram");  // plot_histogram.cc

// Horizontal sigma bars, one row per parameter, in one unit. Where parts are given, the bar is
// split into statistical / systematic / inputs segments in proportion to their share of the
// variance (sigma^2 = stat^2 + sys^2 + inputs^2), so the segments add up to the total.
struct SigmaEntry {
  std::string name;
  double total = 0.0, statistical = 0.0, systematic = 0.0, inputs = 0.0;
};
std::string SigmaBars(const std::vector<SigmaEntry>& entries,
                      const std::string& unit);  // plot_sigma_bars.cc

// The correlation matrix as a heat map (blue -1 .. white 0 .. red +1); cells with |rho| < 0.05
// are left white (not drawn) so that a 140-parameter matrix stays small.
std::string CorrelationHeatmap(
    const std::vector<std::string>& names,
    const std::vector<std::vector<double>>& correlation);  // plot_heatmap.cc

// One row per label: a dot at `value` and a bar from `lo` to `hi` (omitted when lo == hi).
struct IntervalRow {
  std::string label;
  double value = 0.0, lo = 0.0, hi = 0.0;
  int color = 0;  // SeriesColor index
};
std::string IntervalPlot(const std::string& kind, const std::vector<IntervalRow>& rows,
                         const std::string& x_label, const std::string& caption,
                         const std::vector<std::pair<std::string, std::string>>& legend = {},
                         const std::vector<double>& vlines = {});  // plot_intervals.cc

}  // namespace cellmetry::report
