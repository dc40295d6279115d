// report.html's layout rules (svg_plot.h, html_page.h, compare_report.cc), read off the markup
// each plot kind writes: the legend sits right of the data area, never on it; every mark is in
// the data area, and a point beyond the axes is a triangle at the edge, counted in the caption;
// the compare page plots only numeric results that vary; tables scroll sideways. The same page
// rendered in Chromium: tests/test_report_browser.cc.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "cellmetry/report/plots.h"
#include "cellmetry/report/reports.h"

namespace cellmetry {
namespace {

using report::ScatterSpec;
using report::Series;

struct Box {
  double left = 0, top = 0, right = 0, bottom = 0;
};

double Attribute(const std::string& element, const std::string& name) {
  std::smatch m;
  const std::regex pattern(" " + name + "=\"([-0-9.e+]+)\"");
  if (!std::regex_search(element, m, pattern)) ADD_FAILURE() << name << " not in " << element;
  return m.empty() ? 0.0 : std::stod(m[1].str());
}

// The data area: the frame rect marked data-role="plot-area".
Box PlotArea(const std::string& figure) {
  std::smatch m;
  const std::regex frame(R"(<rect[^>]*data-role="plot-area"[^>]*>)");
  EXPECT_TRUE(std::regex_search(figure, m, frame));
  if (m.empty()) return {};
  const std::string rect = m.str();
  const double x = Attribute(rect, "x"), y = Attribute(rect, "y");
  return {x, y, x + Attribute(rect, "width"), y + Attribute(rect, "height")};
}

// The markup between an opening marker and the first "</g>" after it.
std::string Group(const std::string& figure, const std::string& opening) {
  const size_t at = figure.find(opening);
  if (at == std::string::npos) return "";
  return figure.substr(at, figure.find("</g>", at) - at);
}

std::vector<std::string> Elements(const std::string& markup, const std::string& tag) {
  std::vector<std::string> found;
  const std::regex pattern("<" + tag + "\\b[^>]*>");
  for (auto it = std::sregex_iterator(markup.begin(), markup.end(), pattern);
       it != std::sregex_iterator(); ++it) {
    found.push_back(it->str());
  }
  return found;
}

// Every circle centre and every rect of the marks lies in the data area (half a pixel of slack
// for the one-decimal coordinates and a bar's minimum width).
void ExpectMarksInPlotArea(const std::string& figure) {
  const Box area = PlotArea(figure);
  const std::string marks = Group(figure, "<g class=\"marks\">");
  ASSERT_FALSE(marks.empty());
  for (const auto& c : Elements(marks, "circle")) {
    EXPECT_GE(Attribute(c, "cx"), area.left - 0.5) << c;
    EXPECT_LE(Attribute(c, "cx"), area.right + 0.5) << c;
    EXPECT_GE(Attribute(c, "cy"), area.top - 0.5) << c;
    EXPECT_LE(Attribute(c, "cy"), area.bottom + 0.5) << c;
  }
  for (const auto& r : Elements(marks, "rect")) {
    EXPECT_GE(Attribute(r, "x"), area.left - 0.5) << r;
    EXPECT_LE(Attribute(r, "x") + Attribute(r, "width"), area.right + 0.7) << r;
    EXPECT_GE(Attribute(r, "y"), area.top - 0.5) << r;
    EXPECT_LE(Attribute(r, "y") + Attribute(r, "height"), area.bottom + 0.7) << r;
  }
}

// The legend's swatches and labels start right of the data area and end inside the viewBox.
void ExpectLegendBesideThePlot(const std::string& figure) {
  const Box area = PlotArea(figure);
  const std::string legend = figure.substr(figure.find("data-role=\"legend\""));
  ASSERT_NE(figure.find("data-role=\"legend\""), std::string::npos) << "no legend";
  std::smatch m;
  const std::regex view_box(R"re(viewBox="0 0 ([0-9.]+) ([0-9.]+)")re");
  ASSERT_TRUE(std::regex_search(figure, m, view_box));
  const double width = std::stod(m[1].str());
  const auto swatches = Elements(legend, "rect");
  ASSERT_FALSE(swatches.empty());
  for (const auto& r : swatches) {
    EXPECT_GT(Attribute(r, "x"), area.right) << r;
    EXPECT_LT(Attribute(r, "x") + Attribute(r, "width"), width) << r;
  }
  for (const auto& t : Elements(legend, "text")) EXPECT_GT(Attribute(t, "x"), area.right) << t;
}

int DataBeyond(const std::string& figure) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(figure, m, std::regex(R"re(data-beyond="(\d+)")re")));
  return m.empty() ? -1 : std::stoi(m[1].str());
}

int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Two series of residuals in [-1, 1] over capture order, and one gross value of +50.
ScatterSpec ResidualsWithOneGrossValue(bool fenced) {
  ScatterSpec spec;
  spec.kind = "residual_order";
  spec.symmetric_y = true;
  spec.fenced_y = fenced;
  for (int k = 0; k < 2; ++k) {
    Series s;
    s.name = k == 0 ? "tool" : "base";
    for (int i = 0; i < 60; ++i) {
      s.x.push_back(i);
      s.y.push_back(std::sin(0.7 * i + k));
    }
    spec.series.push_back(s);
  }
  spec.series[0].x.push_back(30);
  spec.series[0].y.push_back(50);
  return spec;
}

TEST(ReportLayout, APointAboveTheFencesIsATriangleAtTheTopEdgeAndCounted) {
  const std::string figure = report::ScatterPlot(ResidualsWithOneGrossValue(true));
  EXPECT_EQ(DataBeyond(figure), 1);
  EXPECT_NE(figure.find("1 point beyond the axis, drawn at its edge (triangles)."),
            std::string::npos);
  const auto beyond = Elements(figure, "polygon");  // the beyond marks are the only polygons
  ASSERT_EQ(beyond.size(), 1u);
  EXPECT_NE(beyond[0].find("class=\"beyond\""), std::string::npos);
  // Its base on the top edge, its tip above it: pointing out of the data area, upward.
  const std::regex point(R"(([-0-9.]+),([-0-9.]+))");
  std::vector<double> ys;
  const std::string points = beyond[0].substr(beyond[0].find("points="));
  for (auto it = std::sregex_iterator(points.begin(), points.end(), point);
       it != std::sregex_iterator(); ++it) {
    ys.push_back(std::stod((*it)[2].str()));
  }
  ASSERT_EQ(ys.size(), 3u);
  const Box area = PlotArea(figure);
  EXPECT_LT(ys[0], area.top - 3) << "the tip points up, out of the area";
  EXPECT_NEAR(ys[1], area.top, 0.6);
  EXPECT_NEAR(ys[2], area.top, 0.6);
  // The band is not squashed: the y ticks span the fenced range (about +-1), not +-50.
  const std::string ticks = Group(figure, "<g class=\"ticks\">");
  const std::regex y_tick(R"(text-anchor="end">([-0-9.e+]+)</text>)");
  int y_ticks = 0;
  for (auto it = std::sregex_iterator(ticks.begin(), ticks.end(), y_tick);
       it != std::sregex_iterator(); ++it, ++y_ticks) {
    EXPECT_LE(std::abs(std::stod((*it)[1].str())), 1.5) << it->str();
  }
  EXPECT_GE(y_ticks, 3);
  ExpectMarksInPlotArea(figure);
  ExpectLegendBesideThePlot(figure);
  // The legend takes its room from the data area: the scatter keeps its width (three in a row).
  EXPECT_NE(figure.find("viewBox=\"0 0 380.0 240.0\""), std::string::npos);
}

TEST(ReportLayout, AnUnfencedScatterHoldsEveryPoint) {
  const std::string figure = report::ScatterPlot(ResidualsWithOneGrossValue(false));
  EXPECT_EQ(DataBeyond(figure), 0);
  EXPECT_EQ(figure.find("beyond the axis"), std::string::npos);
  EXPECT_EQ(Count(figure, "<circle"), 121);
  ExpectMarksInPlotArea(figure);
}

// Fences are per series: a world target's residuals, all near 0, must not make a carried
// target's ordinary spread look gross; and a tail that does not at least double the range is
// shown, not clipped.
TEST(ReportLayout, FencesClipOnlyGrossValuesOfEachSeries) {
  ScatterSpec spec = ResidualsWithOneGrossValue(true);
  spec.series[0].x.pop_back();
  spec.series[0].y.pop_back();
  for (double& y : spec.series[1].y) y *= 1e-6;  // a tight band
  spec.series[0].x.insert(spec.series[0].x.end(), {61, 62});
  spec.series[0].y.insert(spec.series[0].y.end(), {1.6, -1.7});  // a tail, not gross
  const std::string figure = report::ScatterPlot(spec);
  EXPECT_EQ(DataBeyond(figure), 0);
  EXPECT_EQ(Count(figure, "<circle"), 122);
  ExpectMarksInPlotArea(figure);
}

TEST(ReportLayout, ABinnedScatterCountsItsPointsBeyondTheFences) {
  ScatterSpec spec = ResidualsWithOneGrossValue(true);
  for (int i = 0; i < 3000; ++i) {
    spec.series[1].x.push_back(i % 60);
    spec.series[1].y.push_back(std::cos(0.3 * i));
  }
  spec.series[1].x.insert(spec.series[1].x.end(), {10, 11});
  spec.series[1].y.insert(spec.series[1].y.end(), {-80, -90});
  const std::string figure = report::ScatterPlot(spec);
  EXPECT_NE(figure.find("density per series"), std::string::npos);
  EXPECT_EQ(DataBeyond(figure), 3);
  EXPECT_NE(figure.find("3 points beyond the axis"), std::string::npos);
  ExpectMarksInPlotArea(figure);
}

TEST(ReportLayout, TheHistogramMarksAndCountsValuesBeyondSix) {
  std::vector<double> whitened;
  for (int i = 0; i < 500; ++i) whitened.push_back(std::sin(1.3 * i) * 2.5);
  whitened.insert(whitened.end(), {-9, 7, 40});
  const std::string figure = report::NormalHistogram(whitened, "residual / sigma");
  EXPECT_EQ(DataBeyond(figure), 3);
  EXPECT_EQ(Count(figure, "class=\"beyond\""), 2);  // one per side
  EXPECT_NE(figure.find("3 points beyond the axis, drawn at its edge"), std::string::npos);
  ExpectMarksInPlotArea(figure);
  ExpectLegendBesideThePlot(figure);
}

TEST(ReportLayout, IntervalsSigmaBarsAndHeatmapHoldEveryMarkWithTheLegendBeside) {
  const std::string intervals = report::IntervalPlot(
      "held_out",
      {{"all cameras, fitted", 0.2, 0.2, 0.2, 0},
       {"all cameras, held out", 0.3, 0.25, 40, 1},
       {"cam1, fitted", -7, -7, -7, 0}},
      "RMS (mm)", "", {{report::SeriesColor(0), "fitted"}, {report::SeriesColor(1), "held out"}});
  EXPECT_EQ(DataBeyond(intervals), 0);
  ExpectMarksInPlotArea(intervals);
  ExpectLegendBesideThePlot(intervals);

  const std::string sigma = report::SigmaBars(
      {{"ur3.base.x", 0.4, 0.3, 0.2, 0.1}, {"ur3.base.rz", 90, 1, 2, 3}, {"tool.z", 0.01}}, "mm");
  ExpectMarksInPlotArea(sigma);
  ExpectLegendBesideThePlot(sigma);

  const std::vector<std::string> names = {"a", "b", "c"};
  const std::string heatmap =
      report::CorrelationHeatmap(names, {{1, 0.9, -0.3}, {0.9, 1, 0.01}, {-0.3, 0.01, 1}});
  ExpectMarksInPlotArea(heatmap);
  ExpectLegendBesideThePlot(heatmap);
}

// A kinematic comparison's table: settings (pose_set, size, formulation, solver, seed), results
// that vary, a floor that was not computed (0 in every row), a text stop reason.
const char kCompareCsv[] =
    "pose_set,size,formulation,solver,mean_mm,max_mm,rms_mm,floor_rms_mm,iterations,time_s,"
    "stop_reason,seed\n"
    "random,50,forward,ceres_lm,0.21,0.52,0.25,0,12,0.5,\"converged\",1\n"
    "random,50,forward,ceres_lm,0.23,0.55,0.27,0,14,0.6,\"converged\",2\n"
    "random,50,forward,pinv,0.31,0.72,0.35,0,30,0.2,\"converged\",1\n"
    "random,50,forward,pinv,0.29,0.70,0.33,0,31,0.3,\"converged\",2\n";

TEST(ReportLayout, ComparePlotsOnlyResultsThatVary) {
  const std::string html = report::CompareReportHtml(kCompareCsv, "", "compare");
  EXPECT_EQ(Count(html, "data-plot=\"compare_column\""), 5);  // mean, max, rms, iterations, time
  for (const char* result : {"mean_mm", "max_mm", "rms_mm", "iterations", "time_s"}) {
    EXPECT_EQ(Count(html, std::string(">") + result + "</text>"), 1) << result;
  }
  for (const char* not_plotted : {"size", "floor_rms_mm", "seed"}) {
    EXPECT_EQ(Count(html, std::string(">") + not_plotted + "</text>"), 0) << not_plotted;
  }
  EXPECT_NE(html.find("Not plotted: size (a setting), floor_rms_mm (0 in every row), "
                      "seed (a setting)."),
            std::string::npos);
  // The size joins the configuration's label: a setting says what a row is.
  EXPECT_NE(html.find(">random / 50 / forward / ceres_lm</text>"), std::string::npos);
}

TEST(ReportLayout, TablesScrollSidewaysAndLongCellsWrap) {
  const std::string long_reason(70, 'x');
  const std::string csv = "solver,error_mm,stop_reason\na,1,ok\nb,2," + long_reason + "\n";
  const std::string html = report::CompareReportHtml(csv, "", "compare");
  EXPECT_EQ(Count(html, "<div class=\"table-scroll\"><table>"), Count(html, "<table>"));
  EXPECT_NE(html.find("<td class=\"wrap\">" + long_reason + "</td>"), std::string::npos);
  EXPECT_NE(html.find(".table-scroll{overflow-x:auto"), std::string::npos);
}

}  // namespace
}  // namespace cellmetry
