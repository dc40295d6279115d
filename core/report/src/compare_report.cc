// CompareReportHtml (reports.h): one plot per numeric result column of a comparison's table.csv
// that varies (PlottedColumns says the rule), each configuration (its settings) with the mean
// over seeds and its 95 % t-interval when the table has a seed column (or a column pair X_lo /
// X_hi as X's interval); then table.md rendered (its tables, recommendation lists and notes) and
// every row of table.csv.
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>

#include "cellmetry/basics/statistics.h"
#include "cellmetry/basics/text.h"
#include "cellmetry/formats/csv_table.h"

#include "cellmetry/report/html_page.h"
#include "cellmetry/report/plots.h"
#include "cellmetry/report/reports.h"

namespace cellmetry::report {
namespace {

bool IsNumber(const std::string& s, double* value) {
  if (s.empty()) return false;
  char* end = nullptr;
  *value = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size();
}

// One markdown table row's cells: "| a | b |" -> {"a", "b"}.
std::vector<std::string> MarkdownCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (size_t i = 1; i < line.size(); ++i) {
    if (line[i] != '|') {
      cell += line[i];
      continue;
    }
    const size_t first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
    cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
    cell.clear();
  }
  return cells;
}

// The part of markdown cellmetry's comparisons write: tables, "- " lists, paragraphs.
void AddMarkdown(const std::string& markdown, HtmlPage* page) {
  std::istringstream in(markdown);
  std::string line, list;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  auto flush = [&] {
    if (!header.empty()) page->Table(header, rows);
    if (!list.empty()) page->Raw("<ul>" + list + "</ul>\n");
    header.clear(), rows.clear(), list.clear();
  };
  while (std::getline(in, line)) {
    if (line.rfind("|", 0) == 0) {
      if (line.rfind("|---", 0) == 0) continue;  // the header's rule
      (header.empty() ? header : rows.emplace_back()) = MarkdownCells(line);
    } else if (line.rfind("- ", 0) == 0) {
      list += "<li>" + EscapeXml(line.substr(2)) + "</li>";
    } else {
      flush();
      if (!line.empty()) page->Paragraph(line);
    }
  }
  flush();
}

// Which columns of table.csv say what a row was run with (settings) and which what it measured.
struct Columns {
  std::vector<bool> numeric;
  std::vector<bool> setting;        // a label or setting: text, or a numeric setting by name
  std::vector<std::string> labels;  // per data row: its settings joined (the configuration)
  int seed = -1;                    // the "seed" column, if any
};

// A numeric column named for what a row was run with rather than what it measured: the seed,
// the size of a pose set, a count of inputs, an index or id.
bool IsSettingName(const std::string& name) {
  auto ends = [&](const std::string& tail) {
    return name.size() >= tail.size() &&
           name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
  };
  for (const char* exact : {"seed", "seeds", "size", "count", "n", "index", "id"}) {
    if (name == exact) return true;
  }
  for (const char* tail : {"_seed", "_size", "_count", "_index", "_id"}) {
    if (ends(tail)) return true;
  }
  return name.rfind("n_", 0) == 0;
}

Columns ClassifyColumns(const std::vector<std::vector<std::string>>& table) {
  const auto& header = table[0];
  Columns columns;
  columns.numeric.assign(header.size(), true);
  for (size_t r = 1; r < table.size(); ++r) {
    for (size_t c = 0; c < header.size(); ++c) {
      double v;
      if (c >= table[r].size() || !IsNumber(table[r][c], &v)) columns.numeric[c] = false;
    }
  }
  for (size_t c = 0; c < header.size(); ++c) {
    if (header[c] == "seed" && columns.numeric[c]) columns.seed = static_cast<int>(c);
    columns.setting.push_back(!columns.numeric[c] || IsSettingName(header[c]));
  }
  for (size_t r = 1; r < table.size(); ++r) {
    std::string label;
    for (size_t c = 0; c < header.size() && c < table[r].size(); ++c) {
      if (!columns.setting[c] || static_cast<int>(c) == columns.seed ||
          header[c].find("stop_reason") != std::string::npos) {
        continue;
      }
      label += (label.empty() ? "" : " / ") + table[r][c];
    }
    columns.labels.push_back(label);
  }
  return columns;
}

// Whether every row holds the same number in column c.
bool IsConstant(const std::vector<std::vector<std::string>>& table, size_t c) {
  double first = 0, v = 0;
  IsNumber(table[1][c], &first);
  for (size_t r = 2; r < table.size(); ++r) {
    IsNumber(table[r][c], &v);
    if (!(v == first) && !(std::isnan(v) && std::isnan(first))) return false;
  }
  return true;
}

// The rule for what the page plots: a numeric result column that varies between rows. Not
// plotted: settings and labels (text, the seed, sizes, counts: IsSettingName), which say what a
// row is, not what it measured; a column equal in every row (an all-zero floor that was not
// computed), whose plot would say nothing the table does not; X_lo / X_hi, drawn as X's interval.
// `skipped` gets why each other numeric column is not plotted, for the page's note.
std::vector<size_t> PlottedColumns(const std::vector<std::vector<std::string>>& table,
                                   const Columns& columns, std::vector<std::string>* skipped) {
  const auto& header = table[0];
  std::vector<size_t> plotted;
  for (size_t c = 0; c < header.size(); ++c) {
    const std::string end = header[c].size() > 3 ? header[c].substr(header[c].size() - 3) : "";
    if (!columns.numeric[c] || end == "_lo" || end == "_hi") continue;
    if (columns.setting[c]) {
      skipped->push_back(header[c] + " (a setting)");
    } else if (IsConstant(table, c)) {
      skipped->push_back(header[c] + " (" + table[1][c] + " in every row)");
    } else {
      plotted.push_back(c);
    }
  }
  return plotted;
}

// Column c per configuration: over seeds, the mean and its 95 % t-interval; one row per
// configuration otherwise, with X_lo / X_hi columns drawn as X's interval when present.
std::vector<IntervalRow> ColumnRows(const std::vector<std::vector<std::string>>& table,
                                    const Columns& columns, size_t c) {
  const auto& header = table[0];
  std::vector<IntervalRow> rows;
  if (columns.seed >= 0) {
    std::vector<std::string> order;
    std::map<std::string, std::vector<double>> values;
    for (size_t r = 1; r < table.size(); ++r) {
      const std::string& label = columns.labels[r - 1];
      if (!values.count(label)) order.push_back(label);
      double v = 0;
      IsNumber(table[r][c], &v);
      values[label].push_back(v);
    }
    for (const auto& label : order) {
      const MeanInterval m = TInterval95(values[label]);
      const bool bounded = std::isfinite(m.low) && std::isfinite(m.high);
      rows.push_back({label, m.mean, bounded ? m.low : m.mean, bounded ? m.high : m.mean, 0});
    }
    return rows;
  }
  int lo = -1, hi = -1;
  for (size_t k = 0; k < header.size(); ++k) {
    if (header[k] == header[c] + "_lo" && columns.numeric[k]) lo = static_cast<int>(k);
    if (header[k] == header[c] + "_hi" && columns.numeric[k]) hi = static_cast<int>(k);
  }
  for (size_t r = 1; r < table.size(); ++r) {
    double v = 0, l = 0, h = 0;
    IsNumber(table[r][c], &v);
    l = h = v;
    if (lo >= 0 && hi >= 0) IsNumber(table[r][lo], &l), IsNumber(table[r][hi], &h);
    rows.push_back({columns.labels[r - 1], v, l, h, 0});
  }
  return rows;
}

}  // namespace

std::string CompareReportHtml(const std::string& csv, const std::string& markdown,
                              const std::string& title) {
  // Row 0 the header, then every data row, each as long as the header.
  const CsvTable csv_table = CsvTable::Parse(csv, "table.csv");
  std::vector<std::vector<std::string>> table = csv_table.rows();
  if (!csv_table.header().empty()) table.insert(table.begin(), csv_table.header());
  HtmlPage page(title, "cellmetry compare: " +
                           std::to_string(table.empty() ? 0 : table.size() - 1) + " table rows");
  if (table.size() < 2) {
    page.Paragraph("The comparison has no rows.");
    return page.Html();
  }
  const auto& header = table[0];
  const Columns columns = ClassifyColumns(table);
  page.Section("Per configuration", "plots");
  page.Note(columns.seed >= 0
                ? "Each numeric result column of table.csv that varies, per configuration: the "
                  "mean over seeds (dot) and its 95 % Student-t interval (bar)."
                : "Each numeric result column of table.csv that varies; each row a "
                  "configuration.");
  std::vector<std::string> skipped;
  const std::vector<size_t> plotted = PlottedColumns(table, columns, &skipped);
  page.BeginGrid();
  for (size_t c : plotted) {
    page.Raw(IntervalPlot("compare_column", ColumnRows(table, columns, c), header[c], ""));
  }
  page.EndGrid();
  if (!skipped.empty()) {
    page.Note("Not plotted: " + Join(skipped) + ".");
  }
  page.Section("Comparison", "comparison");
  AddMarkdown(markdown, &page);
  page.Section("Every row of table.csv", "table");
  std::vector<std::vector<std::string>> body(table.begin() + 1, table.end());
  page.Table(header, body, 200);
  return page.Html();
}

}  // namespace cellmetry::report
