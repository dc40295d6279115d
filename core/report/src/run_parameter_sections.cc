// The run report's parameter sections (run_sections.h): sigma bars, correlations, frames table.
#include <map>

#include "cellmetry/basics/transform.h"

#include "cellmetry/report/plots.h"
#include "run_sections.h"

namespace cellmetry::report {

void SigmaSection(const WorkcellResult& r, HtmlPage* page) {
  page->Section("Sigma of every parameter", "sigma");
  page->Note(
      "1-sigma of every fitted number, in its unit; held entries are left out. Frame "
      "rotations are small rotations about the parent's axes, in mrad.");
  std::map<std::string, std::vector<SigmaEntry>> by_unit;
  const char* kAxes[6] = {"x", "y", "z", "rx", "ry", "rz"};
  for (const auto& f : r.frames) {
    for (int k = 0; k < 6; ++k) {
      if (f.held[k]) continue;
      const double scale = k < 3 ? 1.0 : 1000.0;
      SigmaEntry e;
      e.name = f.name + "." + kAxes[k];
      e.total = scale * (k < 3 ? f.sigma_mm[k] : f.sigma_rad[k - 3]);
      e.statistical = scale * f.sigma_statistical[k];
      e.systematic = scale * f.sigma_systematic[k];
      e.inputs = scale * f.sigma_inputs[k];
      by_unit[k < 3 ? "mm" : "mrad"].push_back(e);
    }
  }
  for (const auto& p : r.model_parameters) {
    if (p.held) continue;
    by_unit[p.unit.empty() ? "-" : p.unit].push_back(
        {p.name, p.sigma, p.sigma_statistical, p.sigma_systematic, p.sigma_inputs});
  }
  page->BeginGrid();
  for (const auto& [unit, entries] : by_unit) page->Raw(SigmaBars(entries, unit));
  page->EndGrid();
}

void CorrelationSection(const WorkcellResult& r, HtmlPage* page) {
  const Uncertainty& u = r.uncertainty;
  if (u.names.empty() || u.correlation.rows() != static_cast<Eigen::Index>(u.names.size())) return;
  page->Section("Correlations of the free parameters", "correlation");
  std::vector<std::vector<double>> c(u.names.size());
  for (size_t i = 0; i < u.names.size(); ++i) {
    for (size_t k = 0; k < u.names.size(); ++k) c[i].push_back(u.correlation(i, k));
  }
  page->Raw(CorrelationHeatmap(u.names, c));
  if (!r.strong_correlations.empty()) {
    std::vector<std::vector<std::string>> rows;
    for (const auto& s : r.strong_correlations) rows.push_back({s.a, s.b, Num(s.correlation, 3)});
    page->Paragraph("Strongly correlated (|rho| >= 0.9): the data moves these together.");
    page->Table({"parameter", "with", "correlation"}, rows, 50);
  }
}

void FramesSection(const WorkcellResult& r, HtmlPage* page) {
  page->Section("Frames", "frames");
  std::vector<std::vector<std::string>> rows;
  auto sigma = [](const FrameEstimate& f, int k, double value) {
    return f.held[k] ? std::string("held") : Num(value, 2);
  };
  for (const auto& f : r.frames) {
    const Eigen::Vector3d t = f.pose.t;
    const Eigen::Vector3d rv = RvecFromRotation(f.pose.R);
    rows.push_back({f.name, f.parent, Num(t.x(), 7), Num(t.y(), 7), Num(t.z(), 7),
                    sigma(f, 0, f.sigma_mm.x()), sigma(f, 1, f.sigma_mm.y()),
                    sigma(f, 2, f.sigma_mm.z()), Num(rv.x(), 5), Num(rv.y(), 5), Num(rv.z(), 5),
                    sigma(f, 3, f.sigma_rad.x()), sigma(f, 4, f.sigma_rad.y()),
                    sigma(f, 5, f.sigma_rad.z())});
  }
  page->Table({"frame", "in", "x mm", "y mm", "z mm", "σx", "σy", "σz", "rx rad", "ry rad",
               "rz rad", "σrx", "σry", "σrz"},
              rows);
  if (!r.model_parameters.empty()) {
    std::vector<std::vector<std::string>> params;
    for (const auto& p : r.model_parameters) {
      params.push_back(
          {p.name, p.unit, Num(p.nominal, 7), Num(p.value, 7), p.held ? "held" : Num(p.sigma, 2)});
    }
    page->Paragraph("Model parameters");
    page->Table({"parameter", "unit", "nominal", "fitted", "sigma"}, params);
  }
}

}  // namespace cellmetry::report
