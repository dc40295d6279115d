// The run report's residual sections (run_sections.h): capture order, whitened, across the image.
#include <cmath>
#include <map>

#include "cellmetry/report/plots.h"
#include "run_sections.h"

namespace cellmetry::report {
namespace {

const char* kAxis[3] = {"x", "y", "depth"};

bool IsPosition(const ResidualRow& row) { return row.kind == ResidualKind::kPosition; }

// Residual rows by camera, then by target (a series per target).
template <typename Fn>
std::map<std::string, std::map<std::string, Series>> ByCameraTarget(const WorkcellResult& r,
                                                                    Fn fill) {
  std::map<std::string, std::map<std::string, Series>> out;
  for (const auto& row : r.residuals) {
    if (!IsPosition(row)) continue;
    Series& s = out[row.camera][row.target];
    s.name = row.target;
    fill(row, &s);
  }
  return out;
}

std::vector<Series> Values(const std::map<std::string, Series>& m) {
  std::vector<Series> v;
  for (const auto& [name, s] : m) v.push_back(s);
  return v;
}

}  // namespace

void ResidualOrderSection(const WorkcellResult& r, const Recording& recording, HtmlPage* page) {
  page->Section("Residuals over capture order", "order");
  page->Note(
      "Prediction minus measurement of every target position, in the camera's axes (mm), "
      "against the sample's place in the recording. A drift, a jump or a block of poses "
      "that disagrees shows here; noise looks like a band around 0.");
  for (int axis = 0; axis < 3; ++axis) {
    const auto cameras = ByCameraTarget(r, [&](const ResidualRow& row, Series* s) {
      s->x.push_back(recording.SampleIndex(row.sample));
      s->y.push_back(row.error[axis]);
    });
    if (axis == 0) page->BeginGrid();
    for (const auto& [camera, targets] : cameras) {
      ScatterSpec spec;
      spec.kind = "residual_order";
      spec.x_label = "capture order (sample index)";
      spec.y_label = camera + " " + kAxis[axis] + " residual (mm)";
      spec.series = Values(targets);
      spec.symmetric_y = true;
      spec.fenced_y = true;  // one gross residual must not flatten the band into a line
      page->Raw(ScatterPlot(spec));
    }
  }
  page->EndGrid();
}

void WhitenedSection(const WorkcellResult& r, HtmlPage* page) {
  page->Section("Whitened residuals against N(0,1)", "whitened");
  page->Note(
      "Every residual component divided by the sigma it was weighted with. If the noise "
      "model is right they follow the red curve; a wider histogram means sigma is too "
      "small (the covariance is scaled up by the reduced chi-square), heavy tails mean "
      "outliers or unmodelled physics.");
  std::vector<double> position, rotation;
  for (const auto& row : r.residuals) {
    auto& into = IsPosition(row) ? position : rotation;
    for (int k = 0; k < 3; ++k) into.push_back(row.normalized[k]);
  }
  page->BeginGrid();
  page->Raw(NormalHistogram(position, "position residual / sigma"));
  if (!rotation.empty()) page->Raw(NormalHistogram(rotation, "rotation residual / sigma"));
  page->EndGrid();
}

void ResidualImageSection(const WorkcellResult& r, const Recording& recording, HtmlPage* page) {
  page->Section("Residuals across the image and against depth", "image");
  page->Note(
      "Each residual axis against the measured position of the target in the same camera "
      "axis, and the residual's length against depth: a slope is a scale or distortion "
      "error of the camera, a curve against depth a depth bias.");
  const int n_obs = static_cast<int>(recording.observations.size());
  for (int panel = 0; panel < 4; ++panel) {
    const auto cameras = ByCameraTarget(r, [&](const ResidualRow& row, Series* s) {
      if (row.observation < 0 || row.observation >= n_obs) return;
      const Eigen::Vector3d& p = recording.observations[row.observation].position_mm;
      s->x.push_back(p[panel < 3 ? panel : 2]);
      s->y.push_back(panel < 3 ? row.error[panel] : row.error.norm());
    });
    if (panel == 0) page->BeginGrid();
    for (const auto& [camera, targets] : cameras) {
      ScatterSpec spec;
      spec.kind = "residual_image";
      spec.x_label = camera + " measured " + (panel < 3 ? kAxis[panel] : "depth") + " (mm)";
      spec.y_label = panel < 3 ? std::string(kAxis[panel]) + " residual (mm)" : "|residual| (mm)";
      spec.series = Values(targets);
      spec.symmetric_y = panel < 3;
      spec.fenced_y = true;
      page->Raw(ScatterPlot(spec));
    }
  }
  page->EndGrid();
}

}  // namespace cellmetry::report
