// report.html (core/report): the pages `run` and `diagnose` write open in a browser without a
// network, log nothing to the console, and draw every plot. Each page is opened in headless
// Chromium (Debian's `chromium`): --dump-dom gives the DOM after the page's load check ran
// (html_page.h: data-plots, data-plots-drawn, data-legend-overlaps), --enable-logging=stderr
// gives every console message, --screenshot keeps a picture in <build>/test_artifacts/report/.
// Without Chromium the DOM-level checks still run on the file and the browser checks are
// skipped, by name.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <regex>

#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/report/reports.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

namespace fs = std::filesystem;

std::string Artifacts() {
  const std::string dir = std::string(CELLMETRY_BUILD_DIR) + "/test_artifacts/report";
  fs::create_directories(dir);
  return dir;
}

bool HaveChromium() { return std::system("command -v chromium >/dev/null 2>&1") == 0; }

int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// What a page must be whatever opens it: self-contained, every plot with marks.
void ExpectSelfContained(const std::string& html) {
  EXPECT_EQ(html.find("http://"),
            html.find("http://www.w3.org/2000/svg"));  // only the SVG namespace
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(Count(html, "data-marks=\"0\""), 0) << "a plot without marks";
}

// Opens `path` in headless Chromium; checks the console and that every plot has a box and marks.
// Returns the number of plots the page's check counted.
int OpenInChromium(const std::string& path, const std::string& name) {
  const std::string dom = Artifacts() + "/" + name + ".dom.html";
  const std::string log = Artifacts() + "/" + name + ".console.txt";
  const std::string flags =
      "chromium --headless --disable-gpu --no-sandbox --virtual-time-budget=3000 "
      "--enable-logging=stderr --v=0 ";
  const std::string url = "file://" + fs::absolute(path).string();
  EXPECT_EQ(
      std::system((flags + "--dump-dom '" + url + "' >'" + dom + "' 2>'" + log + "'").c_str()), 0);
  EXPECT_EQ(std::system((flags + "--window-size=1300,3000 --screenshot='" + Artifacts() + "/" +
                         name + ".png' '" + url + "' >/dev/null 2>&1")
                            .c_str()),
            0);
  const std::string console = testing::ReadText(log);
  std::smatch m;
  EXPECT_FALSE(std::regex_search(console, m, std::regex(R"([^\n]*CONSOLE[^\n]*)"))) << m.str();
  const std::string page = testing::ReadText(dom);
  EXPECT_NE(page.find("data-report-ready=\"1\""), std::string::npos) << "the load check never ran";
  std::smatch plots, drawn;
  EXPECT_TRUE(std::regex_search(page, plots, std::regex(R"re(data-plots="(\d+)")re")));
  EXPECT_TRUE(std::regex_search(page, drawn, std::regex(R"re(data-plots-drawn="(\d+)")re")));
  if (plots.empty() || drawn.empty()) return 0;
  EXPECT_EQ(plots[1].str(), drawn[1].str()) << "plots without a box or marks";
  EXPECT_NE(page.find("data-legend-overlaps=\"0\""), std::string::npos)
      << "a legend drawn over a plot's data area";
  EXPECT_TRUE(fs::exists(Artifacts() + "/" + name + ".png"));
  return std::stoi(plots[1].str());
}

TEST(Report, RunWritesAPageWithEveryPlotDrawn) {
  const std::string out = testing::TempDirForThisTest("report") + "/vsb";
  const auto run = testing::RunCellmetry(
      "-q run " + testing::Source("configs/jobs/vsb_sim_b.yaml") + " -o " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string html = testing::ReadText(out + "/report.html");
  ExpectSelfContained(html);
  for (const char* kind : {"residual_order", "whitened_histogram", "residual_image", "sigma_bars",
                           "correlation_heatmap", "outliers", "held_out"}) {
    EXPECT_GT(Count(html, std::string("data-plot=\"") + kind + "\""), 0) << kind;
  }
  EXPECT_NE(html.find("ur3.base"), std::string::npos);  // the frames table
  fs::copy_file(out + "/report.html", Artifacts() + "/run.html",
                fs::copy_options::overwrite_existing);
  if (!HaveChromium()) GTEST_SKIP() << "chromium is not installed: DOM-level checks only";
  EXPECT_GE(OpenInChromium(out + "/report.html", "run"), 14);
}

// 80,000 residual rows stay a page of bounded size: the scatters turn into densities.
TEST(Report, ManyResidualRowsAreBinnedNotDropped) {
  Recording recording;
  recording.targets = {{"tool", "ur3"}};
  WorkcellResult result;
  std::srand(7);
  auto noise = [] { return std::rand() / double(RAND_MAX) - 0.5; };
  for (int i = 0; i < 80000; ++i) {
    Sample s;
    s.id = i;
    recording.samples.push_back(s);
    Observation o;
    o.sample = i;
    o.camera = i % 2 ? "cam1" : "cam2";
    o.target = "tool";
    o.position_mm = {300 * noise(), 200 * noise(), 1000 + 400 * noise()};
    recording.observations.push_back(o);
    ResidualRow row;
    row.observation = i;
    row.sample = i;
    row.camera = o.camera;
    row.target = "tool";
    row.kind = ResidualKind::kPosition;
    row.error = {noise(), noise(), noise()};
    row.normalized = 3.4 * row.error;
    result.residuals.push_back(row);
  }
  const std::string html = report::RunReportHtml(result, recording, "80,000 rows");
  ExpectSelfContained(html);
  EXPECT_LT(html.size(), 3'000'000u) << "binned plots must keep the page small";
  EXPECT_NE(html.find("points drawn as a 60 x 30 density"), std::string::npos);
  EXPECT_NE(html.find("240000 values"), std::string::npos);  // the histogram counts them all
  testing::WriteText(Artifacts() + "/big.html", html);
  std::printf("report of 80,000 residual rows: %zu bytes\n", html.size());
  if (!HaveChromium()) GTEST_SKIP() << "chromium is not installed: DOM-level checks only";
  EXPECT_GE(OpenInChromium(Artifacts() + "/big.html", "big"), 14);
}

TEST(Report, DiagnoseShowsTheAcceptedEffectsSignature) {
  const std::string dir = testing::TempDirForThisTest("report");
  std::string sim = testing::ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml"));
  sim = testing::ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml",
                             testing::Source("configs/robots/ur3_vsb2020.yaml"));
  sim = testing::ReplaceOnce(sim, "random: 150", "random: 80");
  testing::WriteText(dir + "/sim.yaml", sim);
  WorkcellSimulationSpec spec = LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins());
  testing::ConcealJoint3Compliance(&spec);
  const Recording recording = SimulateWorkcell(spec, nullptr);
  const DiagnosisJob job = testing::Ur3DiagnoseJob(dir);
  const DiagnosisResult d = testing::Diagnose(job, recording, dir + "/job.yaml");
  ASSERT_FALSE(d.accepted.empty());
  ASSERT_FALSE(d.accepted.front().signature.empty());
  const std::string html = report::DiagnoseReportHtml(d, recording, "diagnose test");
  ExpectSelfContained(html);
  EXPECT_GT(Count(html, "data-plot=\"effect_signature\""), 0);
  EXPECT_GT(Count(html, "data-plot=\"candidate_scores\""), 0);
  // One physical finding per site, named by its headline (diagnosis.h, step 7).
  ASSERT_FALSE(d.findings.empty());
  EXPECT_EQ(Count(html, "id=\"findings\""), 1);
  EXPECT_GT(Count(html, "<td>" + d.accepted.at(d.findings.front().headline).label + "</td>"), 0);
  testing::WriteText(Artifacts() + "/diagnose.html", html);
  testing::WriteText(Artifacts() + "/diagnose_final_fit.html",
                     report::RunReportHtml(d.final_fit, recording, "final fit"));
  if (!HaveChromium()) GTEST_SKIP() << "chromium is not installed: DOM-level checks only";
  EXPECT_GE(OpenInChromium(Artifacts() + "/diagnose.html", "diagnose"), 3);
  EXPECT_GE(OpenInChromium(Artifacts() + "/diagnose_final_fit.html", "diagnose_final_fit"), 10);
}

// `cellmetry home` on a simulated delta arm: the page shows the offsets and the homing runs.
TEST(Report, HomeWritesAPageOfItsOffsetsAndRuns) {
  const std::string dir = testing::TempDirForThisTest("report");
  const auto simulated =
      testing::RunCellmetry("simulate " + testing::Source("configs/simulations/delta_homing.yaml") +
                            " -o " + dir + "/sim");
  ASSERT_EQ(simulated.exit_code, 0) << simulated.output;
  std::string job = testing::ReadText(testing::Source("configs/jobs/delta_homing.yaml"));
  job = testing::ReplaceOnce(job, "../../results/delta_homing_sim", dir + "/sim");
  job = testing::ReplaceOnce(job, "../../results/delta_homing", dir + "/out");
  job = testing::ReplaceOnce(job, "../robots/delta.yaml",
                             testing::Source("configs/robots/delta.yaml"));
  testing::WriteText(dir + "/job.yaml", job);
  const auto homed = testing::RunCellmetry("home " + dir + "/job.yaml");
  ASSERT_EQ(homed.exit_code, 0) << homed.output;
  const std::string html = testing::ReadText(dir + "/out/report.html");
  ExpectSelfContained(html);
  EXPECT_EQ(Count(html, "data-plot=\"homing_offsets\""), 1);
  EXPECT_EQ(Count(html, "data-plot=\"homing_runs\""), 1);
  fs::copy_file(dir + "/out/report.html", Artifacts() + "/home.html",
                fs::copy_options::overwrite_existing);
  if (!HaveChromium()) GTEST_SKIP() << "chromium is not installed: DOM-level checks only";
  EXPECT_GE(OpenInChromium(Artifacts() + "/home.html", "home"), 2);
}

// `cellmetry compare` (solvers x camera models, two seeds): the page carries the table with its
// intervals and the recommendations.
TEST(Report, CompareWritesAPageOfItsTable) {
  const std::string dir = testing::TempDirForThisTest("report");
  testing::WriteText(dir + "/spec.yaml",
                     "compare: solvers\njob: " + testing::Source("configs/jobs/vsb_sim_b.yaml") +
                         "\nsolvers: {ceres_lm: {type: ceres_lm}, pinv: {type: jacobian_pinv}}\n"
                         "camera_models: [static_cameras]\nseeds: 2\noutput: " +
                         dir + "/out\n");
  const auto compared = testing::RunCellmetry("compare " + dir + "/spec.yaml");
  ASSERT_EQ(compared.exit_code, 0) << compared.output;
  const std::string html = testing::ReadText(dir + "/out/report.html");
  ExpectSelfContained(html);
  EXPECT_NE(html.find("95 % Student-t interval (bar)"), std::string::npos);  // over seeds
  EXPECT_EQ(Count(html, "data-plot=\"compare_column\""), 3);              // error, time, iterations
  EXPECT_NE(html.find("<th>held-out RMS (mm)</th>"), std::string::npos);  // table.md, rendered
  EXPECT_NE(html.find("<li>for this cell, static_cameras, which solver: "), std::string::npos);
  fs::copy_file(dir + "/out/report.html", Artifacts() + "/compare.html",
                fs::copy_options::overwrite_existing);
  if (!HaveChromium()) GTEST_SKIP() << "chromium is not installed: DOM-level checks only";
  EXPECT_GE(OpenInChromium(Artifacts() + "/compare.html", "compare"), 1);
}

}  // namespace
}  // namespace cellmetry
