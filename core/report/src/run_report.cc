// RunReportHtml (reports.h): the page `cellmetry run` writes beside result.json.
#include "cellmetry/report/html_page.h"
#include "cellmetry/report/reports.h"
#include "cellmetry/report/svg_plot.h"
#include "run_sections.h"

namespace cellmetry::report {
namespace {

void SummarySection(const WorkcellResult& r, HtmlPage* page) {
  page->Section("Summary", "summary");
  const Uncertainty& u = r.uncertainty;
  const std::string held_out = Num(r.held_out.total.norm, 4) + " ± " +
                               Num(r.held_out.total_se_mm, 2) + " over " +
                               std::to_string(r.held_out.folds) + " folds";
  page->Table({"", ""}, {{"solver", r.solver.solver + ", " + std::to_string(r.solver.iterations) +
                                        " iterations, " +
                                        (r.solver.converged ? "converged" : "NOT converged") +
                                        " (" + r.solver.stop_reason + ")"},
                         {"residual rows", std::to_string(r.residuals.size())},
                         {"chi-square / dof", Num(u.chi2, 5) + " / " + std::to_string(u.dof) +
                                                  " = " + Num(u.reduced_chi2, 4)},
                         {"covariance scale", Num(u.scale, 4)},
                         {"condition number", Num(u.condition_number, 3)},
                         {"held-out RMS (mm)", held_out},
                         {"outliers left out", std::to_string(r.outliers.size())},
                         {"not determined by the data (held or by a prior)",
                          std::to_string(r.unidentifiable.size())}});
  for (const auto& w : r.warnings) page->Paragraph("Warning: " + w);
  for (const auto& p : r.unidentifiable) {
    page->Note((p.prior_sigma > 0
                    ? "by its plausible size as a prior (0 +- " + Num(p.prior_sigma, 3) + "): "
                    : std::string("held: ")) +
               p.name + " (" + p.reason + ")");
  }
}

}  // namespace

std::string RunReportHtml(const WorkcellResult& result, const Recording& recording,
                          const std::string& title) {
  HtmlPage page(title, "cellmetry run: " + std::to_string(result.frames.size()) + " frames, " +
                           std::to_string(result.uncertainty.names.size()) +
                           " free parameters, recording " + recording.folder);
  SummarySection(result, &page);
  FramesSection(result, &page);
  SigmaSection(result, &page);
  CorrelationSection(result, &page);
  ResidualOrderSection(result, recording, &page);
  WhitenedSection(result, &page);
  ResidualImageSection(result, recording, &page);
  HeldOutSection(result, recording, &page);
  HeldOutSetupSection(result, &page);
  CamerasLeftOutSection(result, &page);
  OutlierSection(result, recording, &page);
  return page.Html();
}

}  // namespace cellmetry::report
