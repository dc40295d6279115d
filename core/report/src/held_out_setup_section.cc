// The run report's held-out setup section (run_sections.h): the same robot in another setup,
// its frames registered again, the other poses scored against their predicted sigma.
#include <cmath>
#include <string>
#include <vector>

#include "cellmetry/cell/joint_ranges.h"
#include "cellmetry/report/svg_plot.h"
#include "run_sections.h"

namespace cellmetry::report {

void HeldOutSetupSection(const WorkcellResult& r, HtmlPage* page) {
  if (!r.held_out_setup) return;
  const HeldOutSetupScore& v = *r.held_out_setup;
  page->Section("Held-out setup", "held-out-setup");
  page->Note("The calibrated geometry kept, the frames this job frees registered again on " +
             std::to_string(v.registration_poses.size()) + " poses of " + v.recording +
             ", and the other " + std::to_string(v.scored_poses) +
             " poses scored. Each point's predicted sigma carries the calibration's uncertainty "
             "of the geometry, the registration's of the frames, and the new setup's own "
             "scatter about the model; about 95 % of the points lie inside their 95 % "
             "ellipsoid when the sigma are honest.");
  const std::vector<std::vector<std::string>> rows = {
      {"calibrated geometry", Num(v.rms_mm, 4) + " ± " + Num(v.rms_se_mm, 4), Num(v.mean_mm, 4),
       Num(v.max_mm, 4)},
      {"nominal geometry", Num(v.nominal_rms_mm, 4), "", ""},
      {"registration poses (calibrated)", Num(v.registration_rms_mm, 4), "", ""}};
  page->Table({"model", "RMS (mm)", "mean (mm)", "max (mm)"}, rows, 10);
  page->Paragraph(
      "The RMS's ± is its standard error over the scored poses, taken as independent "
      "draws (the registration's own error, shared by every point, is not in it). "
      "Predicted sigma of a point (median of its 3D sigma): " +
      Num(v.median_sigma_mm, 4) +
      " mm; inside their 95 % ellipsoid: " + Num(100.0 * v.within_95, 1) +
      " % of the points; mean of e'C^-1 e / 3: " + Num(v.mean_normalized, 2) +
      " (1 when the sigma are right).");
  const std::string beyond = BeyondCalibrationText(v);
  if (!beyond.empty()) page->Paragraph(beyond);
}

}  // namespace cellmetry::report
