// SvgPlot (svg_plot.h): axes, nice ticks and marks as SVG markup.
#include "cellmetry/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace cellmetry::report {
namespace {

// About `target` round tick values (1, 2, 5 x 10^k) covering [lo, hi].
std::vector<double> NiceTicks(double lo, double hi, int target = 5) {
  std::vector<double> ticks;
  const double span = hi - lo;
  if (!(span > 0) || !std::isfinite(span)) return ticks;
  const double raw = span / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * magnitude;
    if (step >= raw) break;
  }
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * span; t += step) {
    ticks.push_back(std::abs(t) < 1e-12 * span ? 0.0 : t);
  }
  return ticks;
}

std::string F(double px) {  // pixel coordinates: one decimal is plenty
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", px);
  return buffer;
}

std::string TitleTag(const std::string& title) {
  return title.empty() ? "" : "<title>" + EscapeXml(title) + "</title>";
}

// `values`' finite values within their Tukey far fences, all of them where the fences say
// nothing (few values, no spread between the quartiles).
std::vector<double> WithinFences(const std::vector<double>& values, double fence) {
  std::vector<double> finite;
  for (double v : values) {
    if (std::isfinite(v)) finite.push_back(v);
  }
  if (finite.size() < 20) return finite;
  std::vector<double> sorted = finite;
  std::sort(sorted.begin(), sorted.end());
  auto quantile = [&](double q) {
    const double at = q * static_cast<double>(sorted.size() - 1);
    const size_t below = static_cast<size_t>(at);
    const size_t above = std::min(below + 1, sorted.size() - 1);
    return sorted[below] + (at - static_cast<double>(below)) * (sorted[above] - sorted[below]);
  };
  const double q1 = quantile(0.25), q3 = quantile(0.75), iqr = q3 - q1;
  if (!(iqr > 0)) return finite;
  std::vector<double> inside;
  for (double v : finite) {
    if (v >= q1 - fence * iqr && v <= q3 + fence * iqr) inside.push_back(v);
  }
  return inside;
}

constexpr size_t kLegendLongest = 30;  // characters shown; the full label is the entry's title
constexpr double kLegendCharPx = 6.4, kLegendRowPx = 14;

std::string LegendLabel(const std::string& label) {
  if (label.size() <= kLegendLongest) return label;
  size_t cut = kLegendLongest - 1;
  while (cut > 0 && (label[cut] & 0xC0) == 0x80) --cut;  // whole UTF-8 characters
  return label.substr(0, cut) + "~";
}

}  // namespace

Range RangeOf(const std::vector<double>& values, bool with_zero, double pad) {
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (!std::isfinite(lo)) return {-1, 1};
  if (with_zero) {
    lo = std::min(lo, 0.0);
    hi = std::max(hi, 0.0);
  }
  if (hi - lo <= 1e-300)
    return {lo - std::max(1.0, std::abs(lo)), hi + std::max(1.0, std::abs(hi))};
  const double margin = pad * (hi - lo);
  return {with_zero && lo == 0.0 ? 0.0 : lo - margin, hi + margin};
}

Range Union(Range a, Range b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }

Range FencedRangeOf(const std::vector<std::vector<double>>& populations, double fence, double pad) {
  std::vector<double> all, kept;
  for (const auto& values : populations) {
    all.insert(all.end(), values.begin(), values.end());
    const std::vector<double> inside = WithinFences(values, fence);
    kept.insert(kept.end(), inside.begin(), inside.end());
  }
  const Range every = RangeOf(all, false, pad), fenced = RangeOf(kept, false, pad);
  const bool gross = (every.hi - every.lo) > 2 * (fenced.hi - fenced.lo);
  return gross && !kept.empty() ? fenced : every;
}

std::string Num(double value, int digits) {
  if (!std::isfinite(value)) return std::isnan(value) ? "n/a" : (value > 0 ? "inf" : "-inf");
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

const char* SeriesColor(int index) {
  static const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                  "#9467bd", "#8c564b", "#e377c2", "#17becf"};
  return kColors[((index % 8) + 8) % 8];
}

SvgPlot::SvgPlot(std::string kind, double width, double height)
    : kind_(std::move(kind)), width_(width), height_(height) {}

void SvgPlot::SetX(Range range, std::string label) {
  x_ = range;
  x_label_ = std::move(label);
}
void SvgPlot::SetY(Range range, std::string label) {
  y_ = range;
  y_label_ = std::move(label);
}
void SvgPlot::SetYCategories(std::vector<std::string> names, std::string label) {
  categories_ = std::move(names);
  y_ = {static_cast<double>(categories_.size()) - 0.5, -0.5};  // first row on top
  y_label_ = std::move(label);
}

double SvgPlot::Px(double x) const {
  return left_ + (x - x_.lo) / (x_.hi - x_.lo) * (width_ - left_ - right_);
}
double SvgPlot::Py(double y) const {
  return height_ - bottom_ - (y - y_.lo) / (y_.hi - y_.lo) * (height_ - top_ - bottom_);
}

bool SvgPlot::Holds(double x, double y) const {
  return x >= std::min(x_.lo, x_.hi) && x <= std::max(x_.lo, x_.hi) &&
         y >= std::min(y_.lo, y_.hi) && y <= std::max(y_.lo, y_.hi);
}

void SvgPlot::Circle(double x, double y, double r_px, const std::string& color,
                     const std::string& title, double opacity) {
  if (!std::isfinite(x) || !std::isfinite(y)) return;
  if (!Holds(x, y)) {
    BeyondMark(x, y, color, title);
    return;
  }
  body_ += "<circle cx=\"" + F(Px(x)) + "\" cy=\"" + F(Py(y)) + "\" r=\"" + F(r_px) + "\" fill=\"" +
           color + "\" fill-opacity=\"" + Num(opacity, 2) + "\">" + TitleTag(title) + "</circle>";
  ++marks_;
}

void SvgPlot::BeyondMark(double x, double y, const std::string& color, const std::string& title,
                         int count) {
  if (!std::isfinite(x) || !std::isfinite(y) || count <= 0) return;
  const double ex = std::clamp(x, std::min(x_.lo, x_.hi), std::max(x_.lo, x_.hi));
  const double ey = std::clamp(y, std::min(y_.lo, y_.hi), std::max(y_.lo, y_.hi));
  const double px = Px(ex), py = Py(ey);
  // Outward: from the edge point toward where the point lies, in pixels.
  double ux = Px(x) - px, uy = Py(y) - py;
  const double length = std::hypot(ux, uy);
  if (length > 0) {
    ux /= length, uy /= length;
  } else {
    ux = 0, uy = -1;
  }
  const double tip = 7, half = 4.5;  // px: a triangle larger than any point, so it stands out
  const std::string points = F(px + tip * ux) + "," + F(py + tip * uy) + " " + F(px - half * uy) +
                             "," + F(py + half * ux) + " " + F(px + half * uy) + "," +
                             F(py - half * ux);
  const std::string note = (count > 1 ? std::to_string(count) + " points" : "a point") +
                           " beyond the axis, drawn at its edge";
  body_ += "<polygon class=\"beyond\" points=\"" + points + "\" fill=\"" + color +
           "\" stroke=\"#222\" stroke-width=\"0.8\">" +
           TitleTag(title.empty() ? note : title + " (" + note + ")") + "</polygon>";
  ++marks_;
  beyond_ += count;
}

void SvgPlot::Rect(double x0, double y0, double x1, double y1, const std::string& color,
                   double opacity, const std::string& title) {
  if (!std::isfinite(x0 + y0 + x1 + y1)) return;
  const double px0 = Px(x0), px1 = Px(x1), py0 = Py(y0), py1 = Py(y1);
  body_ += "<rect x=\"" + F(std::min(px0, px1)) + "\" y=\"" + F(std::min(py0, py1)) +
           "\" width=\"" + F(std::max(0.6, std::abs(px1 - px0))) + "\" height=\"" +
           F(std::max(0.6, std::abs(py1 - py0))) + "\" fill=\"" + color + "\"" +
           (opacity < 1 ? " fill-opacity=\"" + Num(opacity, 2) + "\"" : std::string()) + ">" +
           TitleTag(title) + "</rect>";
  ++marks_;
}

void SvgPlot::Polyline(const std::vector<double>& xs, const std::vector<double>& ys,
                       const std::string& color, double width_px, const std::string& dash) {
  std::string points;
  for (size_t i = 0; i < xs.size() && i < ys.size(); ++i) {
    if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) continue;
    points += F(Px(xs[i])) + "," + F(Py(ys[i])) + " ";
  }
  if (points.empty()) return;
  body_ += "<polyline fill=\"none\" stroke=\"" + color + "\" stroke-width=\"" + Num(width_px, 3) +
           "\"" + (dash.empty() ? "" : " stroke-dasharray=\"" + dash + "\"") + " points=\"" +
           points + "\"/>";
  ++marks_;
}

void SvgPlot::HLine(double y, const std::string& color, const std::string& dash) {
  if (!std::isfinite(y) || y < std::min(y_.lo, y_.hi) || y > std::max(y_.lo, y_.hi)) return;
  body_ += "<line x1=\"" + F(left_) + "\" x2=\"" + F(width_ - right_) + "\" y1=\"" + F(Py(y)) +
           "\" y2=\"" + F(Py(y)) + "\" stroke=\"" + color + "\" stroke-dasharray=\"" + dash +
           "\"/>";
}

void SvgPlot::VLine(double x, const std::string& color, const std::string& dash) {
  if (!std::isfinite(x) || x < std::min(x_.lo, x_.hi) || x > std::max(x_.lo, x_.hi)) return;
  body_ += "<line y1=\"" + F(top_) + "\" y2=\"" + F(height_ - bottom_) + "\" x1=\"" + F(Px(x)) +
           "\" x2=\"" + F(Px(x)) + "\" stroke=\"" + color + "\" stroke-dasharray=\"" + dash +
           "\"/>";
}

void SvgPlot::Legend(const std::vector<std::pair<std::string, std::string>>& color_label) {
  legend_ = color_label;
}

double SvgPlot::LegendWidth(const std::vector<std::pair<std::string, std::string>>& color_label) {
  size_t longest = 0;
  for (const auto& entry : color_label) {
    longest = std::max(longest, LegendLabel(entry.second).size());
  }
  return color_label.empty() ? 0.0 : 16 + kLegendCharPx * static_cast<double>(longest);
}

// The legend as a column to the right of the data area: `width` and `height` grow to hold it.
std::string SvgPlot::LegendSvg(double* width, double* height) const {
  if (legend_.empty()) return "";
  const double lx = width_ - right_ + 12;
  std::ostringstream s;
  s << "<g class=\"legend\" data-role=\"legend\">";
  double y = top_;
  for (const auto& [color, label] : legend_) {
    s << "<g>" << TitleTag(label) << "<rect x=\"" << F(lx) << "\" y=\"" << F(y + 2)
      << "\" width=\"9\" height=\"9\" fill=\"" << color << "\"/><text x=\"" << F(lx + 12)
      << "\" y=\"" << F(y + 10) << "\">" << EscapeXml(LegendLabel(label)) << "</text></g>";
    y += kLegendRowPx;
  }
  s << "</g>";
  *width = std::max(*width, width_ + LegendWidth(legend_));
  *height = std::max(*height, y + 6);
  return s.str();
}

std::string SvgPlot::CaptionText() const {
  if (beyond_ == 0) return caption_;
  const std::string note =
      (beyond_ == 1 ? std::string("1 point") : std::to_string(beyond_) + " points") +
      " beyond the axis, drawn at its edge (triangles).";
  return caption_.empty() ? note : caption_ + " " + note;
}

std::string SvgPlot::Svg() const {
  double width = width_, height = height_;
  const std::string legend = LegendSvg(&width, &height);
  std::ostringstream s;
  s << "<figure class=\"plot\" data-plot=\"" << EscapeXml(kind_) << "\" data-marks=\"" << marks_
    << "\" data-beyond=\"" << beyond_ << "\"><svg xmlns=\"http://www.w3.org/2000/svg\" width=\""
    << F(width) << "\" height=\"" << F(height) << "\" viewBox=\"0 0 " << F(width) << " "
    << F(height) << "\">";
  const double x0 = left_, x1 = width_ - right_, y0 = top_, y1 = height_ - bottom_;
  s << "<rect class=\"frame\" data-role=\"plot-area\" x=\"" << F(x0) << "\" y=\"" << F(y0)
    << "\" width=\"" << F(x1 - x0) << "\" height=\"" << F(y1 - y0) << "\"/>";
  s << "<g class=\"ticks\">";
  for (double t : NiceTicks(x_.lo, x_.hi)) {
    s << "<line x1=\"" << F(Px(t)) << "\" x2=\"" << F(Px(t)) << "\" y1=\"" << F(y1) << "\" y2=\""
      << F(y1 + 4) << "\"/><text x=\"" << F(Px(t)) << "\" y=\"" << F(y1 + 15)
      << "\" text-anchor=\"middle\">" << Num(t, 4) << "</text>";
  }
  if (categories_.empty()) {
    for (double t : NiceTicks(y_.lo, y_.hi)) {
      s << "<line class=\"grid\" x1=\"" << F(x0) << "\" x2=\"" << F(x1) << "\" y1=\"" << F(Py(t))
        << "\" y2=\"" << F(Py(t)) << "\"/><text x=\"" << F(x0 - 5) << "\" y=\"" << F(Py(t) + 3.5)
        << "\" text-anchor=\"end\">" << Num(t, 4) << "</text>";
    }
  } else {
    for (size_t i = 0; i < categories_.size(); ++i) {
      s << "<text x=\"" << F(x0 - 5) << "\" y=\"" << F(Py(static_cast<double>(i)) + 3.5)
        << "\" text-anchor=\"end\">" << EscapeXml(categories_[i]) << "</text>";
    }
  }
  s << "</g>";
  if (x_.lo < 0 && x_.hi > 0 && categories_.empty()) {
    s << "<line class=\"zero\" x1=\"" << F(Px(0)) << "\" x2=\"" << F(Px(0)) << "\" y1=\"" << F(y0)
      << "\" y2=\"" << F(y1) << "\"/>";
  }
  if (std::min(y_.lo, y_.hi) < 0 && std::max(y_.lo, y_.hi) > 0 && categories_.empty()) {
    s << "<line class=\"zero\" x1=\"" << F(x0) << "\" x2=\"" << F(x1) << "\" y1=\"" << F(Py(0))
      << "\" y2=\"" << F(Py(0)) << "\"/>";
  }
  s << "<g class=\"marks\">" << body_ << "</g>";
  s << "<text class=\"label\" x=\"" << F((x0 + x1) / 2) << "\" y=\"" << F(height_ - 6)
    << "\" text-anchor=\"middle\">" << EscapeXml(x_label_) << "</text>";
  if (categories_.empty()) {
    s << "<text class=\"label\" transform=\"translate(12," << F((y0 + y1) / 2)
      << ") rotate(-90)\" text-anchor=\"middle\">" << EscapeXml(y_label_) << "</text>";
  }
  s << legend << "</svg>";
  const std::string caption = CaptionText();
  if (!caption.empty()) s << "<figcaption>" << EscapeXml(caption) << "</figcaption>";
  s << "</figure>";
  return s.str();
}

}  // namespace cellmetry::report
