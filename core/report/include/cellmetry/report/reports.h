// report.html for each command that writes a result folder: one self-contained page (style, plots
// and its one check script inline, nothing fetched) to look at before trusting the numbers.
//
//   run       residuals over capture order per camera and axis, whitened residuals against
//             N(0,1), residuals across the image and against depth, sigma of every parameter
//             with its parts, the correlation heat map, outliers, held-out against fitted RMS,
//             the frames table with sigma                                    (run_report.cc)
//   diagnose  each accepted effect's signature (residual against the effect's prediction before
//             and after it was fitted), the rounds' candidates, the regressors (diagnose_report.cc)
//   home      the homing offsets of both methods with their intervals        (home_report.cc)
//   compare   each figure per configuration with its 95 % interval; the table (compare_report.cc)
//
// Every plot is inline SVG (svg_plot.h, plots.h); large inputs are binned, never truncated
// (plots.h says how), so a report stays a few hundred kilobytes at 80,000 residual rows.
// The functions only build text; the commands write it into their staged output folder
// (atomic_file.h), so report.html is committed with the rest or not at all.
#pragma once

#include <string>

#include "cellmetry/cell/homing.h"
#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/diagnosis/diagnosis.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry::report {

inline constexpr const char* kReportFile = "report.html";

// `recording`: the one the result was fitted on (measured positions, capture order).
std::string RunReportHtml(const WorkcellResult& result, const Recording& recording,
                          const std::string& title);
std::string DiagnoseReportHtml(const DiagnosisResult& result, const Recording& recording,
                               const std::string& title);
std::string HomeReportHtml(const HomingResult& result, const std::string& title);
// `csv`: the comparison's table.csv (header row, then one row per configuration); `markdown`:
// its table.md, shown as preformatted text below the plots.
std::string CompareReportHtml(const std::string& csv, const std::string& markdown,
                              const std::string& title);

}  // namespace cellmetry::report
