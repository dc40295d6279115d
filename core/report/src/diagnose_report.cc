// DiagnoseReportHtml (reports.h): the physics finder's findings, each accepted effect's signature.
#include <algorithm>
#include <map>

#include "cellmetry/basics/text.h"
#include "cellmetry/report/html_page.h"
#include "cellmetry/report/plots.h"
#include "cellmetry/report/reports.h"

namespace cellmetry::report {
namespace {

const char* kAxis[3] = {"x", "y", "depth"};

void FitRow(const std::string& name, const FitSummary& f,
            std::vector<std::vector<std::string>>* rows) {
  rows->push_back({name, Num(f.chi2, 5), Num(f.dof, 5), Num(f.p_value, 3), Num(f.rms_mm, 4),
                   Num(f.held_out_rms_mm, 4) + " ± " + Num(f.held_out_rms_se_mm, 2),
                   Num(f.held_out_sigma, 4)});
}

// Residual against the effect's prediction, before and after, one plot pair per camera and axis.
void SignatureSection(const AcceptedEffect& a, HtmlPage* page) {
  page->Paragraph(
      a.name + ": " + a.description + " (largest tool displacement " + Num(a.peak_mm, 3) + " mm" +
      (a.aliases.empty() ? "" : "; these poses cannot tell it from " + Join(a.aliases)) + ")");
  std::map<std::pair<std::string, int>, std::pair<Series, Series>> panels;
  for (const auto& p : a.signature) {
    auto& [before, after] = panels[{p.camera, p.axis}];
    before.name = "before";
    after.name = "after";
    before.x.push_back(p.predicted_mm);
    before.y.push_back(p.before_mm);
    after.x.push_back(p.predicted_mm);
    after.y.push_back(p.after_mm);
  }
  if (panels.empty()) {
    page->Note("It moves no carried-target position row: no signature to plot.");
    return;
  }
  page->BeginGrid();
  for (const auto& [key, series] : panels) {
    ScatterSpec spec;
    spec.kind = "effect_signature";
    spec.x_label = "predicted by " + a.name + ", " + key.first + " " + kAxis[key.second] + " (mm)";
    spec.y_label = "residual (mm)";
    spec.series = {series.first, series.second};
    spec.symmetric_y = true;
    spec.caption =
        "Before (geometry alone) a real effect lies along slope -1 (residual = "
        "prediction - measurement); after it is fitted, a flat band.";
    page->Raw(ScatterPlot(spec));
  }
  page->EndGrid();
}

void CandidatesSection(const DiagnosisResult& r, HtmlPage* page) {
  page->Section("Candidates, round by round", "candidates");
  for (size_t k = 0; k < r.rounds.size(); ++k) {
    const DiagnosisRound& round = r.rounds[k];
    const std::string accepted =
        round.accepted.empty() ? "nothing accepted" : "accepted " + round.accepted;
    page->Paragraph("Round " + std::to_string(k + 1) + " (dispersion " + Num(round.dispersion, 3) +
                    "): " + accepted);
    std::vector<std::vector<std::string>> rows;
    std::vector<IntervalRow> scores;
    for (const auto& c : round.candidates) {
      rows.push_back({c.label, std::to_string(c.dof), Num(c.score, 4), Num(c.p_holm, 3),
                      c.refitted ? Num(c.likelihood_ratio, 4) : "",
                      c.refitted ? Num(c.delta_bic, 4) : "",
                      c.cv_gain_se > 0 ? Num(c.cv_gain, 3) + " ± " + Num(c.cv_gain_se, 2) : "",
                      c.bootstrap_share > 0 ? Num(c.bootstrap_share, 3) : "", Num(c.unabsorbed, 3),
                      c.accepted ? "accepted" : Join(c.failed)});
      if (scores.size() < 25) {
        scores.push_back({c.label, c.score, c.score, c.score, c.accepted ? 2 : 0});
      }
    }
    page->Raw(IntervalPlot("candidate_scores", scores, "score statistic (chi-square)",
                           "The round's strongest " + std::to_string(scores.size()) +
                               " candidates by score; green: accepted."));
    page->Table({"candidate", "dof", "score", "p (Holm)", "LR", "ΔBIC", "CV gain (σ)", "bootstrap",
                 "unabsorbed", "verdict"},
                rows, 60);
  }
  if (!r.untestable.empty()) {
    std::vector<std::vector<std::string>> rows;
    for (const auto& c : r.untestable) {
      rows.push_back({c.label, c.untestable_because, c.data_needed});
    }
    page->Paragraph("Untestable with these poses");
    page->Table({"candidate", "because", "what would make it testable"}, rows, 100);
  }
}

// One row per physical finding (step 7 of diagnosis.h): its headline, the effects at its site
// that passed their own test, and those that are the headline's residual shape.
void FindingsSection(const DiagnosisResult& r, HtmlPage* page) {
  if (r.findings.empty()) return;
  page->Section("Physical findings (accepted effects grouped by site)", "findings");
  auto labels = [&](const std::vector<int>& indices) {
    std::string text;
    for (const int i : indices) {
      const AcceptedEffect& a = r.accepted.at(i);
      text += (text.empty() ? "" : "; ") + a.label + " (" + Num(100 * a.group_share, 2) +
              " % of the group's gain, shape " + Num(a.headline_correlation, 2) + ")";
    }
    return text.empty() ? std::string("-") : text;
  };
  std::vector<std::vector<std::string>> rows;
  for (const PhysicalFinding& f : r.findings) {
    rows.push_back({f.site.empty() ? "-" : f.site, r.accepted.at(f.headline).label,
                    labels(f.separate), labels(f.residual_shape),
                    Num(f.held_out_excess_removed, 3)});
  }
  page->Table({"site", "finding (headline)", "also physics here", "its residual shape",
               "held-out excess removed (σ²)"},
              rows);
  page->Note(
      "An effect at a finding's site counts as physics of its own when it removes at "
      "least " +
      Num(100 * r.min_group_share, 2) +
      " % of the group's held-out excess or is shaped unlike the headline (correlation "
      "below " +
      Num(r.shape_correlation, 2) + ").");
}

}  // namespace

std::string DiagnoseReportHtml(const DiagnosisResult& r, const Recording& recording,
                               const std::string& title) {
  HtmlPage page(title, "cellmetry diagnose: " + std::to_string(r.accepted.size()) +
                           " effects accepted, recording " + recording.folder);
  page.Section("Summary", "summary");
  std::vector<std::vector<std::string>> fits;
  FitRow("geometry alone", r.geometric, &fits);
  FitRow("with accepted effects", r.final, &fits);
  page.Table({"model", "chi-square", "dof", "p (vs floor)", "RMS mm", "held-out mm", "held-out σ"},
             fits);
  if (!r.accepted.empty()) {
    page.Paragraph("The accepted effects take " + Num(r.held_out_gain.gain_mm, 3) + " ± " +
                   Num(r.held_out_gain.standard_error_mm, 2) + " mm off the held-out RMS (" +
                   (r.held_out_gain.paired ? "paired: the same rows" : "unpaired") +
                   "). Each ± takes the held-out poses as independent; the folds share training "
                   "poses, so read it as a lower bound.");
  }
  page.Paragraph("Noise floor: " + r.noise_source + ", " + Num(r.floor_rms_mm, 3) + " mm RMS. " +
                 (r.unexplained.empty() ? "What remains is consistent with noise."
                                        : "Unexplained: " + r.unexplained + "."));
  const std::string tie = DiagnosisTie(r);
  if (!tie.empty()) page.Paragraph(tie);
  const std::string advice = PlanAgainstRivalAdvice(r);
  if (!advice.empty()) page.Paragraph("Next: " + advice);
  FindingsSection(r, &page);
  page.Section("Accepted effects and their signatures", "accepted");
  if (r.accepted.empty()) page.Paragraph("No effect passed every test.");
  for (const auto& a : r.accepted) {
    SignatureSection(a, &page);
    std::vector<std::vector<std::string>> rows;
    for (const auto& p : a.parameters) {
      rows.push_back({p.name, p.unit, Num(p.value, 5), Num(p.sigma, 2)});
    }
    page.Table({"parameter", "unit", "value", "sigma"}, rows);
  }
  CandidatesSection(r, &page);
  page.Section("Where the geometric fit's residuals follow the recording", "regressors");
  std::vector<IntervalRow> bars;
  std::vector<std::vector<std::string>> rows;
  for (const auto& f : r.regressors) {
    if (bars.size() < 20) {
      bars.push_back({f.regressor + " (" + f.axis + ")", f.partial_correlation, 0,
                      f.partial_correlation, f.p_value < 0.01 ? 1 : 0});
    }
    rows.push_back({f.regressor, f.axis, Num(f.partial_correlation, 3), Num(f.p_value, 3)});
  }
  if (!bars.empty()) {
    page.Raw(IntervalPlot("regressors", bars, "partial correlation with the residuals",
                          "Strongest 20; red: significant at 0.01 (Bonferroni)."));
  }
  page.Table({"regressor", "axis", "partial correlation", "p (Bonferroni)"}, rows, 60);
  return page.Html();
}

}  // namespace cellmetry::report
