// HomeReportHtml (reports.h): visual homing offsets of both methods, with their intervals, and
// the validation reruns' residual intervals.
#include "cellmetry/report/html_page.h"
#include "cellmetry/report/plots.h"
#include "cellmetry/report/reports.h"

namespace cellmetry::report {

std::string HomeReportHtml(const HomingResult& r, const std::string& title) {
  HtmlPage page(title, "cellmetry home: " + std::to_string(r.positions) + " usable positions, " +
                           (r.validated ? "validated" : "NOT validated"));
  const bool increments = r.increment_rad > 0;
  const double scale = increments ? 1.0 / r.increment_rad : 1000.0;
  const std::string unit = increments ? "motor increments" : "mrad";
  page.Section("Homing offsets", "offsets");
  page.Paragraph("Validation: " + r.validation);
  for (const auto& w : r.warnings) page.Paragraph("Warning: " + w);
  std::vector<IntervalRow> rows;
  std::vector<std::vector<std::string>> table;
  for (int m = 0; m < 3; ++m) {
    const std::string motor = "motor " + std::to_string(m + 1);
    const double io = r.interval_offset_rad[m] * scale, iw = r.interval_width_rad[m] * scale;
    const double lo = r.lsq_offset_rad[m] * scale, ls = r.lsq_sigma_rad[m] * scale;
    rows.push_back({motor + ", interval", io, io - iw / 2, io + iw / 2, 0});
    rows.push_back({motor + ", least squares ± 3σ", lo, lo - 3 * ls, lo + 3 * ls, 1});
    table.push_back({motor, Num(io, 4), Num(iw, 3), Num(lo, 4), Num(ls, 3)});
  }
  page.Raw(IntervalPlot("homing_offsets", rows, "offset (" + unit + ")",
                        "Interval algorithm: offset and the width of the first run's intersection; "
                        "least squares: offset ± 3σ.",
                        {{SeriesColor(0), "interval"}, {SeriesColor(1), "least squares"}}));
  page.Table({"motor", "interval offset", "interval width", "least-squares offset", "σ"}, table);
  page.Section("Runs: the residual intervals", "runs");
  page.Note(
      "Each run intersects the positions' intervals; a rerun measures what remains after "
      "the offset is applied, and the offset stands when that interval holds 0.");
  std::vector<IntervalRow> residual;
  std::vector<std::vector<std::string>> runs;
  for (size_t k = 0; k < r.runs.size(); ++k) {
    const HomingRun& run = r.runs[k];
    for (int m = 0; m < 3; ++m) {
      const double lo = run.lower_rad[m] * scale, hi = run.upper_rad[m] * scale;
      residual.push_back({(k == 0 ? "first run" : "rerun " + std::to_string(k)) + ", motor " +
                              std::to_string(m + 1),
                          (lo + hi) / 2, lo, hi, m});
    }
    runs.push_back({std::to_string(k), std::to_string(run.samples.size()),
                    std::to_string(run.rejected.size())});
  }
  if (!residual.empty()) {
    page.Raw(IntervalPlot("homing_runs", residual, "interval (" + unit + ")",
                          "Dashed: 0. A rerun's interval is of the residual offset.", {}, {0.0}));
  }
  page.Table({"run", "positions intersected", "positions rejected"}, runs);
  return page.Html();
}

}  // namespace cellmetry::report
