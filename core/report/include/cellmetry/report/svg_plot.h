// SvgPlot: one plot as inline SVG markup, drawn from C++ with no script and no library.
//
// Contract: a plot maps data coordinates into a fixed pixel box (SetX, SetY), marks are added in
// data coordinates, and Svg() returns one self-contained `<figure class="plot" data-plot=KIND
// data-marks=N data-beyond=M>` with axes, nice ticks, axis labels with units, the marks and a
// caption. Every mark is plain markup, so a test can count them and a browser needs nothing but
// SVG to show them. Non-finite values are never drawn (they are skipped by the callers' ranges
// and marks). Hover titles (`<title>`) give exact values without a script.
//
// Layout rules, so that nothing hides data:
//  - the data area is the frame `<rect data-role="plot-area">`; the legend
//    (`<g data-role="legend">`) is drawn to the right of it, the viewBox widened (and made
//    taller if the entries need it), never over the marks;
//  - a point outside the axes' ranges is never cut off: Circle draws it at the edge it lies
//    beyond as a triangle pointing outward (BeyondMark, class "beyond"), and the caption says how
//    many points were drawn so. Callers pick ranges that hold every point unless they clip on
//    purpose for readability (FencedRangeOf).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "cellmetry/formats/xml_escape.h"  // EscapeXml, used by every page and plot

namespace cellmetry::report {

struct Range {
  double lo = 0.0;
  double hi = 1.0;
};

// The finite values' range, widened by `pad` of its span; a degenerate range becomes +-1 around
// its value; `with_zero` stretches it to include 0.
Range RangeOf(const std::vector<double>& values, bool with_zero = false, double pad = 0.05);
Range Union(Range a, Range b);

// A range for values a few gross ones must not squash. Each population (a plot's series: the
// residuals of different targets differ in spread) keeps its values within Tukey's far fences
// [Q1 - k IQR, Q3 + k IQR] (k = `fence`), or all of them with fewer than 20 finite values or no
// spread between its quartiles; the range is RangeOf the kept values. It clips only where that
// buys readability: unless the values beyond stretch the range to more than twice the kept
// span, it is RangeOf every value. The values beyond it are drawn at the edge (BeyondMark).
Range FencedRangeOf(const std::vector<std::vector<double>>& populations, double fence = 3.0,
                    double pad = 0.05);

// "1.23", "0.000456", "1.2e+06": %.{digits}g without trailing noise.
std::string Num(double value, int digits = 4);

// A palette for series (cameras, axes, parts); wraps around.
const char* SeriesColor(int index);

class SvgPlot {
 public:
  explicit SvgPlot(std::string kind, double width = 380, double height = 250);

  void SetX(Range range, std::string label);
  void SetY(Range range, std::string label);
  // Categories on the y axis (top to bottom) instead of numbers; the y range becomes
  // [-0.5, n - 0.5] with row i at i.
  void SetYCategories(std::vector<std::string> names, std::string label);
  void SetMarginLeft(double px) { left_ = px; }

  double Px(double x) const;  // data -> pixels
  double Py(double y) const;

  // Whether (x, y) lies within the axes' ranges (edges included).
  bool Holds(double x, double y) const;
  // A point at (x, y); one outside the ranges becomes a BeyondMark.
  void Circle(double x, double y, double r_px, const std::string& color,
              const std::string& title = "", double opacity = 0.8);
  // `count` points at or toward (x, y), outside the ranges: a triangle on the edge they lie
  // beyond, pointing outward; they are added to beyond() and named in the caption.
  void BeyondMark(double x, double y, const std::string& color, const std::string& title = "",
                  int count = 1);
  void Rect(double x0, double y0, double x1, double y1, const std::string& color,
            double opacity = 1.0, const std::string& title = "");
  void Polyline(const std::vector<double>& xs, const std::vector<double>& ys,
                const std::string& color, double width_px = 1.5, const std::string& dash = "");
  void HLine(double y, const std::string& color, const std::string& dash = "4 3");
  void VLine(double x, const std::string& color, const std::string& dash = "4 3");
  void Legend(const std::vector<std::pair<std::string, std::string>>& color_label);
  // How much wider the SVG grows for this legend (0 for none): a plot that must keep its total
  // width (a grid of three) is made this much narrower.
  static double LegendWidth(const std::vector<std::pair<std::string, std::string>>& color_label);
  void Caption(std::string text) { caption_ = std::move(text); }

  int marks() const { return marks_; }
  int beyond() const { return beyond_; }
  std::string Svg() const;

 private:
  std::string LegendSvg(double* width, double* height) const;
  std::string CaptionText() const;

  std::string kind_;
  double width_, height_;
  double left_ = 58, right_ = 14, top_ = 14, bottom_ = 42;
  Range x_, y_;
  std::string x_label_, y_label_, caption_;
  std::vector<std::string> categories_;
  std::vector<std::pair<std::string, std::string>> legend_;
  std::string body_;
  int marks_ = 0;
  int beyond_ = 0;
};

}  // namespace cellmetry::report
