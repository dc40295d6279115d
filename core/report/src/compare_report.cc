// CompareReportHtml (reports.h): a comparison's table.csv as a table and one dot plot per numeric
// column (rows labelled by the text columns). The comparisons compute no intervals today, so
// none are drawn; a column pair named X_lo / X_hi would be drawn as X's interval.
#include <cstdlib>
#include <sstream>

#include "cellmetry/report/html_page.h"
#include "cellmetry/report/plots.h"
#include "cellmetry/report/reports.h"

namespace cellmetry::report {
namespace {

// RFC 4180 enough for what cellmetry writes: commas, double quotes around a field.
std::vector<std::vector<std::string>> ParseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') field += '"', ++i;
      else if (c == '"') quoted = false;
      else field += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      row.push_back(field), field.clear();
    } else if (c == '\n') {
      row.push_back(field), field.clear();
      rows.push_back(row), row.clear();
    } else if (c != '\r') {
      field += c;
    }
  }
  if (!field.empty() || !row.empty()) row.push_back(field), rows.push_back(row);
  return rows;
}

bool IsNumber(const std::string& s, double* value) {
  if (s.empty()) return false;
  char* end = nullptr;
  *value = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size();
}

}  // namespace

std::string CompareReportHtml(const std::string& csv, const std::string& markdown,
                              const std::string& title) {
  const auto table = ParseCsv(csv);
  HtmlPage page(title, "cellmetry compare: " +
                           std::to_string(table.empty() ? 0 : table.size() - 1) + " configurations");
  if (table.size() < 2) {
    page.Paragraph("The comparison has no rows.");
    return page.Html();
  }
  const auto& header = table[0];
  std::vector<bool> numeric(header.size(), true);
  for (size_t r = 1; r < table.size(); ++r) {
    for (size_t c = 0; c < header.size(); ++c) {
      double v;
      if (c >= table[r].size() || !IsNumber(table[r][c], &v)) numeric[c] = false;
    }
  }
  std::vector<std::string> labels;
  for (size_t r = 1; r < table.size(); ++r) {
    std::string label;
    for (size_t c = 0; c < header.size() && c < table[r].size(); ++c) {
      if (!numeric[c] && header[c] != "stop_reason") label += (label.empty() ? "" : " / ") + table[r][c];
    }
    labels.push_back(label);
  }
  page.Section("Per configuration", "plots");
  page.Note("One plot per numeric column of table.csv; each row a configuration.");
  page.BeginGrid();
  for (size_t c = 0; c < header.size(); ++c) {
    const std::string end = header[c].size() > 3 ? header[c].substr(header[c].size() - 3) : "";
    if (!numeric[c] || end == "_lo" || end == "_hi") continue;  // drawn as intervals
    int lo = -1, hi = -1;
    for (size_t k = 0; k < header.size(); ++k) {
      if (header[k] == header[c] + "_lo" && numeric[k]) lo = static_cast<int>(k);
      if (header[k] == header[c] + "_hi" && numeric[k]) hi = static_cast<int>(k);
    }
    std::vector<IntervalRow> rows;
    for (size_t r = 1; r < table.size(); ++r) {
      double v = 0, l = 0, h = 0;
      IsNumber(table[r][c], &v);
      l = h = v;
      if (lo >= 0 && hi >= 0) IsNumber(table[r][lo], &l), IsNumber(table[r][hi], &h);
      rows.push_back({labels[r - 1], v, l, h, 0});
    }
    page.Raw(IntervalPlot("compare_column", rows, header[c], ""));
  }
  page.EndGrid();
  page.Section("Table", "table");
  std::vector<std::vector<std::string>> body(table.begin() + 1, table.end());
  page.Table(header, body);
  page.Raw("<pre>" + EscapeXml(markdown) + "</pre>");
  return page.Html();
}

}  // namespace cellmetry::report
