// report.html's layout as a browser draws it: a run page (configs/jobs/vsb_sim_b.yaml on the
// bundled tests/data/vsb/sim_b) and a compare page (a small table written here, wider than the
// window) are opened in headless Chromium in a 1,400 x 900 window. --dump-dom returns the DOM
// after the page's own load check measured the rendered layout (html_page.h): the document's
// scroll width (no sideways page overflow: wide tables scroll inside their container), every
// plot's rendered legend box against its data area, every plot drawn. --screenshot keeps a
// picture in <build>/test_artifacts/report_browser/. A page that breaks the rules is checked the
// same way, so the check is seen to fail. Without Chromium the tests skip, by name.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include "cellmetry/report/html_page.h"
#include "cellmetry/report/reports.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

namespace fs = std::filesystem;

constexpr int kWindowWidth = 1400, kWindowHeight = 900;

bool HaveChromium() { return std::system("command -v chromium >/dev/null 2>&1") == 0; }

std::string Artifacts() {
  const std::string dir = std::string(CELLMETRY_BUILD_DIR) + "/test_artifacts/report_browser";
  fs::create_directories(dir);
  return dir;
}

// Headless Chromium in the test's window, its own profile, stopped after 60 s whatever happens.
std::string Chromium(const std::string& profile) {
  return "timeout 60 chromium --headless --no-sandbox --disable-gpu --window-size=" +
         std::to_string(kWindowWidth) + "," + std::to_string(kWindowHeight) + " --user-data-dir='" +
         profile + "' --virtual-time-budget=3000 ";
}

// What the page's load check measured (html_page.h), -1 where it set nothing.
struct Layout {
  int plots = -1, plots_drawn = -1, legend_overlaps = -1, page_width = -1, window_width = -1,
      tables_scrolling = -1;
  bool ready = false;
};

int HtmlAttribute(const std::string& dom, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(dom, m, std::regex("<html[^>]* " + name + "=\"(\\d+)\""))) return -1;
  return std::stoi(m[1].str());
}

// Opens `path` in Chromium: the DOM after load (written beside the screenshot) and a screenshot
// of the window, <name>.png.
Layout Render(const std::string& path, const std::string& name) {
  const std::string url = "file://" + fs::absolute(path).string();
  const std::string dom_file = Artifacts() + "/" + name + ".dom.html";
  const std::string browser = Chromium(testing::TempDir("report_browser_profile/" + name));
  EXPECT_EQ(
      std::system((browser + "--dump-dom '" + url + "' >'" + dom_file + "' 2>/dev/null").c_str()),
      0);
  EXPECT_EQ(std::system((browser + "--screenshot='" + Artifacts() + "/" + name + ".png' '" + url +
                         "' >/dev/null 2>&1")
                            .c_str()),
            0);
  const std::string dom = testing::ReadText(dom_file);
  Layout layout;
  layout.ready = dom.find("data-report-ready=\"1\"") != std::string::npos;
  layout.plots = HtmlAttribute(dom, "data-plots");
  layout.plots_drawn = HtmlAttribute(dom, "data-plots-drawn");
  layout.legend_overlaps = HtmlAttribute(dom, "data-legend-overlaps");
  layout.page_width = HtmlAttribute(dom, "data-page-width");
  layout.window_width = HtmlAttribute(dom, "data-window-width");
  layout.tables_scrolling = HtmlAttribute(dom, "data-tables-scrolling");
  return layout;
}

// The screenshot is a PNG of the window, large enough to hold more than a blank page.
void ExpectScreenshot(const std::string& name) {
  const std::string png = Artifacts() + "/" + name + ".png";
  ASSERT_TRUE(fs::exists(png)) << png;
  const std::string bytes = testing::ReadText(png);
  ASSERT_GT(bytes.size(), 24u);
  EXPECT_EQ(bytes.substr(0, 8), "\x89PNG\r\n\x1a\n");
  auto big_endian = [&](size_t at) {
    unsigned value = 0;
    for (size_t i = 0; i < 4; ++i) value = (value << 8) | static_cast<unsigned char>(bytes[at + i]);
    return static_cast<int>(value);
  };
  EXPECT_EQ(big_endian(16), kWindowWidth);  // IHDR
  EXPECT_EQ(big_endian(20), kWindowHeight);
  EXPECT_GT(bytes.size(), 20'000u) << "a near-blank screenshot";
}

// The layout rules of a page that keeps them.
void ExpectLayoutHolds(const Layout& layout, int min_plots) {
  ASSERT_TRUE(layout.ready) << "the page's load check never ran";
  EXPECT_EQ(layout.window_width, kWindowWidth);
  EXPECT_GT(layout.page_width, 0);
  EXPECT_LE(layout.page_width, kWindowWidth) << "the page overflows the window sideways";
  EXPECT_GE(layout.plots, min_plots);
  EXPECT_EQ(layout.plots_drawn, layout.plots) << "plots without a box or marks";
  EXPECT_EQ(layout.legend_overlaps, 0) << "a legend drawn over a plot's data area";
}

TEST(ReportBrowser, TheRunPageFitsTheWindowWithLegendsBesideThePlots) {
  if (!HaveChromium()) GTEST_SKIP() << "chromium is not installed: no browser to render in";
  const std::string out = testing::TempDirForThisTest("report_browser") + "/vsb";
  const auto run = testing::RunCellmetry(
      "-q run " + testing::Source("configs/jobs/vsb_sim_b.yaml") + " -o " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Layout layout = Render(out + "/report.html", "run");
  ExpectLayoutHolds(layout, 14);
  ExpectScreenshot("run");
}

// A kinematic comparison's table.csv, two configurations x two seeds, with more result columns
// than a 1,400 px window holds side by side and the solver's long stop reason.
std::string WideCompareCsv() {
  std::string csv = "pose_set,size,formulation,solver,floor_rms_mm";
  for (int j = 1; j <= 6; ++j) {
    for (const char* what : {"mean", "max", "rms"}) {
      csv += ",joint" + std::to_string(j) + "_" + what + "_mrad";
    }
  }
  csv += ",time_s,stop_reason,seed\n";
  for (const char* solver : {"ceres_lm", "jacobian_pinv"}) {
    for (int seed = 1; seed <= 2; ++seed) {
      csv += std::string("random,50,forward,") + solver + ",0";
      const double scale = (seed + 0.37) * (solver[0] == 'c' ? 1.0 : 1.6);
      for (int k = 0; k < 18; ++k) csv += "," + std::to_string(0.123456789 * (k + 1) * scale);
      csv += "," + std::to_string(0.4 * seed) +
             ",\"Function tolerance reached. |cost_change|/cost: 1.2345e-12 <= 1e-10\"," +
             std::to_string(seed) + "\n";
    }
  }
  return csv;
}

const char kCompareMarkdown[] =
    "Which solver, for this cell (results/compare_kinematic/with/a/long/path/that/has/no/spaces/"
    "in/it/anywhere/at/all/table.csv):\n"
    "\n"
    "| solver | mean (mm) | max (mm) |\n"
    "|---|---|---|\n"
    "| ceres_lm | 0.21 [0.19, 0.23] | 0.52 [0.50, 0.55] |\n"
    "| jacobian_pinv | 0.31 [0.29, 0.33] | 0.72 [0.70, 0.74] |\n"
    "\n"
    "- for this cell, which solver: ceres_lm\n";

TEST(ReportBrowser, TheComparePageFitsTheWindowAndItsWideTableScrolls) {
  if (!HaveChromium()) GTEST_SKIP() << "chromium is not installed: no browser to render in";
  const std::string path = testing::TempDirForThisTest("report_browser") + "/report.html";
  testing::WriteText(path, report::CompareReportHtml(WideCompareCsv(), kCompareMarkdown,
                                                     "cellmetry compare: a wide table"));
  const Layout layout = Render(path, "compare");
  ExpectLayoutHolds(layout, 19);
  EXPECT_GE(layout.tables_scrolling, 1) << "the wide table should scroll in its container";
  ExpectScreenshot("compare");
}

// A figure whose legend lies on its data area and a line wider than the window: the same check
// must report both, or the tests above could not fail.
TEST(ReportBrowser, TheCheckSeesALegendOnTheDataAreaAndAPageTooWide) {
  if (!HaveChromium()) GTEST_SKIP() << "chromium is not installed: no browser to render in";
  report::HtmlPage page("a page that breaks the layout rules");
  page.Raw(
      "<figure class=\"plot\"><svg xmlns=\"http://www.w3.org/2000/svg\" width=\"300\" "
      "height=\"200\" viewBox=\"0 0 300 200\"><rect data-role=\"plot-area\" x=\"40\" "
      "y=\"10\" width=\"250\" height=\"150\" fill=\"#fff\" stroke=\"#999\"/>"
      "<g class=\"marks\"><circle cx=\"50\" cy=\"20\" r=\"3\"/></g><g data-role=\"legend\">"
      "<rect x=\"46\" y=\"14\" width=\"9\" height=\"9\"/><text x=\"58\" y=\"22\">on the "
      "points</text></g></svg></figure>");
  page.Raw("<div style=\"width:2000px\">a line wider than the window</div>");
  const std::string path = testing::TempDirForThisTest("report_browser") + "/broken.html";
  testing::WriteText(path, page.Html());
  const Layout layout = Render(path, "broken");
  ASSERT_TRUE(layout.ready);
  EXPECT_EQ(layout.legend_overlaps, 1);
  EXPECT_GT(layout.page_width, kWindowWidth);
}

}  // namespace
}  // namespace cellmetry
