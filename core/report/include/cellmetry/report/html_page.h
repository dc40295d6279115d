// HtmlPage: a self-contained HTML report page (no network: style, script and plots inline).
//
// Contract: sections, paragraphs, tables and plots (SvgPlot::Svg markup) are appended in reading
// order; Html() returns one document whose only script is a check that runs after load: it
// measures every `figure.plot svg` and sets `data-plots` (how many), `data-plots-drawn` (how many
// have a nonzero box and at least one mark) on <html>, and `data-report-ready="1"`. Nothing on
// the page needs that script to be read; it is there so that a browser test (tests/test_report.cc)
// can see that every plot rendered.
#pragma once

#include <string>
#include <vector>

namespace cellmetry::report {

class HtmlPage {
 public:
  explicit HtmlPage(std::string title, std::string subtitle = "");

  void Section(const std::string& heading, const std::string& id = "");
  void Paragraph(const std::string& text);        // escaped
  void Note(const std::string& text);             // escaped, smaller and grey
  void Raw(const std::string& markup);            // already-safe markup (plots)
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
