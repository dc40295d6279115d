// HtmlPage: a self-contained HTML report page (no network: style, script and plots inline).
//
// Contract: sections, paragraphs, tables and plots (SvgPlot::Svg markup) are appended in reading
// order; Html() returns one document whose only script is a check that runs after load: it
// measures every `figure.plot svg` and sets on <html> `data-plots` (how many),
// `data-plots-drawn` (how many have a nonzero box and at least one mark),
// `data-legend-overlaps` (how many plots' rendered legend box crosses their data area),
// `data-page-width` (the document's scroll width), `data-window-width` (the window's),
// `data-tables-scrolling` (how many tables are wider than the page and scroll in their
// container) and `data-report-ready="1"`. Nothing on the page needs that script to be read; it
// is there so that the browser tests (tests/test_report.cc, tests/test_report_browser.cc) can
// see that every plot rendered and the layout holds.
//
// Layout: the page fits a 1,400 px window; every table is in a container that scrolls sideways
// when the table is wider than the page, and long cells wrap.
#pragma once

#include <string>
#include <vector>

namespace cellmetry::report {

class HtmlPage {
 public:
  explicit HtmlPage(std::string title, std::string subtitle = "");

  void Section(const std::string& heading, const std::string& id = "");
  void Paragraph(const std::string& text);  // escaped
  void Note(const std::string& text);       // escaped, smaller and grey
  void Raw(const std::string& markup);      // already-safe markup (plots)
  // A table; cells are escaped. `max_rows` > 0 keeps the first rows and says how many were left.
  void Table(const std::vector<std::string>& header,
             const std::vector<std::vector<std::string>>& rows, int max_rows = 0);
  void BeginGrid();  // plots side by side until EndGrid
  void EndGrid();

  std::string Html() const;

 private:
  std::string title_, subtitle_, body_, toc_;
};

}  // namespace cellmetry::report
