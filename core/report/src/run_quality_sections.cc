// The run report's quality sections (run_sections.h): outliers, held-out against fitted RMS.
#include <algorithm>
#include <cmath>
#include <map>

#include "cellmetry/cell/joint_ranges.h"
#include "cellmetry/report/plots.h"
#include "run_sections.h"

namespace cellmetry::report {

void OutlierSection(const WorkcellResult& r, const Recording& recording, HtmlPage* page) {
  page->Section("Outliers", "outliers");
  if (r.outliers.empty()) {
    page->Paragraph("No observation failed the outlier test.");
    return;
  }
  page->Paragraph(std::to_string(r.outliers.size()) +
                  " residual rows failed the outlier test; their observations were left out of "
                  "the fit (outliers.csv). Score: how many times the robust scale they lie out.");
  ScatterSpec spec;
  spec.kind = "outliers";
  spec.x_label = "capture order (sample index)";
  spec.y_label = "score (q / s^2)";
  std::map<std::string, Series> by_camera;
  double threshold = 0;
  for (const auto& o : r.outliers) {
    Series& s = by_camera[o.camera];
    s.name = o.camera;
    s.x.push_back(recording.SampleIndex(o.sample));
    s.y.push_back(o.score);
    s.titles.push_back(o.camera + "/" + o.target + " " + o.kind + ", sample " +
                       std::to_string(o.sample) + ": " + Num(o.score, 3));
    threshold = std::max(threshold, o.threshold);
  }
  for (auto& [camera, s] : by_camera) spec.series.push_back(s);
  if (threshold > 0) spec.hlines.push_back(threshold);
  spec.caption = "Dashed: the test's threshold (chi-square quantile).";
  page->Raw(ScatterPlot(spec));
  std::vector<std::vector<std::string>> rows;
  for (const auto& o : r.outliers) {
    rows.push_back({std::to_string(o.line), std::to_string(o.sample), o.camera, o.target, o.kind,
                    Num(o.score, 4), Num(o.threshold, 4)});
  }
  page->Table({"line", "sample", "camera", "target", "kind", "score", "threshold"}, rows, 200);
}

void HeldOutSection(const WorkcellResult& r, const Recording& recording, HtmlPage* page) {
  page->Section("Held-out against fitted RMS", "held-out");
  page->Note(
      "Fitted: RMS of the 3D residual over the carried targets' positions the fit saw. "
      "Held out: the same for poses left out of the fit (k-fold by pose), the bar spans "
      "the folds. Held out much above fitted means the model fits noise or the poses do "
      "not cover the cell.");
  std::vector<IntervalRow> rows;
  std::map<std::string, ResidualRms> fitted;
  ResidualRms all;
  for (const auto& row : r.residuals) {
    if (row.kind != ResidualKind::kPosition) continue;
    auto t = recording.targets.find(row.target);
    if (t != recording.targets.end() && t->second == kWorldCarrier) continue;
    fitted[row.camera].Add(row.error);
    all.Add(row.error);
  }
  all.Finish();
  for (auto& [camera, rms] : fitted) rms.Finish();
  if (all.count > 0) rows.push_back({"all cameras, fitted", all.norm, all.norm, all.norm, 0});
  if (r.held_out.folds > 0) {
    double lo = r.held_out.total.norm, hi = lo;
    for (const auto& f : r.held_out.per_fold) {
      if (f.count == 0) continue;
      lo = std::min(lo, f.norm);
      hi = std::max(hi, f.norm);
    }
    rows.push_back({"all cameras, held out", r.held_out.total.norm, lo, hi, 1});
  }
  for (const auto& [camera, rms] : fitted) {
    rows.push_back({camera + ", fitted", rms.norm, rms.norm, rms.norm, 0});
    auto h = r.held_out.per_camera.find(camera);
    if (h != r.held_out.per_camera.end()) {
      rows.push_back({camera + ", held out", h->second.norm, h->second.norm, h->second.norm, 1});
    }
  }
  if (r.validation) {
    rows.push_back({"validation recording, after", r.validation->after.norm,
                    r.validation->after.norm, r.validation->after.norm, 2});
  }
  if (rows.empty()) {
    page->Paragraph("No carried target positions: nothing to compare.");
    return;
  }
  page->Raw(IntervalPlot("held_out", rows, "RMS of the 3D residual (mm)",
                         std::to_string(r.held_out.folds) + " folds by pose.",
                         {{SeriesColor(0), "fitted"}, {SeriesColor(1), "held out"}}));
  const std::string beyond = r.validation ? BeyondCalibrationText(*r.validation) : "";
  if (!beyond.empty()) page->Paragraph("Validation recording: " + beyond);
}

void CamerasLeftOutSection(const WorkcellResult& r, HtmlPage* page) {
  if (r.cameras_left_out.empty()) return;
  page->Section("Each camera left out", "cameras-left-out");
  page->Note(
      "The cell identified again without each camera, against the answer with all of "
      "them: the difference and its sigma (the data's part from both fits' shared rows, "
      "and the uncertain inputs both share). Beyond " +
      Num(r.cameras_left_out.front().flag_sigmas, 2) +
      " sigma (3 sigma's 0.27 % shared over every coordinate compared) the camera "
      "disagrees with the others more than the model allows: its "
      "intrinsics, its mount, or camera-side physics the job leaves out.");
  std::vector<std::vector<std::string>> rows;
  for (const CameraLeftOut& c : r.cameras_left_out) {
    if (!c.error.empty()) {
      rows.push_back({c.camera, "", "", "", "", "not identifiable without it: " + c.error});
      continue;
    }
    for (const FrameDifference& d : c.frames) {
      for (int i = 0; i < 6; ++i) {
        if (!d.compared[i]) continue;
        const double sigmas = std::abs(d.difference[i]) / d.sigma[i];
        rows.push_back({c.camera, d.frame + "." + kFrameParameterNames[i], Num(d.difference[i], 4),
                        Num(d.sigma[i], 3), Num(sigmas, 2),
                        sigmas > c.flag_sigmas ? "flagged" : ""});
      }
    }
  }
  page->Table(
      {"without", "coordinate", "difference (mm | rad)", "sigma", "|difference| / sigma", ""}, rows,
      200);
}

}  // namespace cellmetry::report
