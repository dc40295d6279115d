// CsvTable (csv_table.h): a CSV file read with its line numbers, so that a missing, non-numeric
// or non-finite cell is an InputError naming its file, line and column.
#include "cellmetry/formats/csv_table.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/input_file.h"
#include "cellmetry/formats/quoted_text.h"

namespace cellmetry {
namespace {

std::string Trim(const std::string& s) {
  const size_t begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  const size_t end = s.find_last_not_of(" \t\r");
  return s.substr(begin, end - begin + 1);
}

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') {
      cell += '"';  // RFC 4180: a doubled quote inside a quoted cell is one quote
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      cells.push_back(Trim(cell));
      cell.clear();
    } else {
      cell += c;
    }
  }
  cells.push_back(Trim(cell));
  return cells;
}

}  // namespace

CsvTable CsvTable::Read(const std::string& path) {
  CsvTable table = Parse(ReadRegularFile(path, kMaxTableBytes, "Check that the file exists"), path);
  if (table.header_.empty()) {
    throw InputError({path, 1, 0}, "file is empty", "The first line must be the column header");
  }
  return table;
}

CsvTable CsvTable::Parse(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  CsvTable table;
  table.path_ = path;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    // A UTF-8 byte-order mark (spreadsheet exports write one) is not part of the first column.
    if (line_number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (Trim(line).empty() || line[0] == '#') continue;
    if (table.header_.empty()) {
      table.header_ = SplitCsvLine(line);
      continue;
    }
    auto cells = SplitCsvLine(line);
    if (cells.size() > table.header_.size()) {
      throw InputError({path, line_number, 0},
                       "row has " + std::to_string(cells.size()) + " cells but the header has " +
                           std::to_string(table.header_.size()),
                       "Remove the extra cells or add their column to the header");
    }
    cells.resize(table.header_.size());  // short rows: trailing optional cells left empty
    table.rows_.push_back(std::move(cells));
    table.lines_.push_back(line_number);
  }
  return table;
}

std::optional<size_t> CsvTable::ColumnIndex(const std::string& name) const {
  for (size_t i = 0; i < header_.size(); ++i) {
    if (header_[i] == name) return i;
  }
  return std::nullopt;
}

void CsvTable::RequireColumns(const std::vector<std::string>& names) const {
  for (const auto& name : names) {
    if (HasColumn(name)) continue;
    std::string present;
    for (const auto& h : header_) present += (present.empty() ? "" : ",") + QuotedShort(h);
    throw InputError({path_, 1, 0}, "missing column '" + name + "'",
                     "The header must name it; the header is: " + present);
  }
}

void CsvTable::RejectUnknownColumns(const std::vector<std::string>& known) const {
  for (size_t i = 0; i < header_.size(); ++i) {
    bool ok = false;
    for (const auto& k : known) ok = ok || k == header_[i];
    if (ok) continue;
    const std::string nearest = NearestWord(header_[i], known);
    throw InputError({path_, 1, static_cast<int>(i + 1)},
                     "unknown column '" + QuotedShort(header_[i]) + "'",
                     nearest.empty() ? "Remove it or rename it to a known column"
                                     : "Did you mean '" + nearest + "'?");
  }
}

InputError CsvTable::Error(size_t row, const std::string& column, const std::string& what,
                           const std::string& hint) const {
  const auto index = ColumnIndex(column);
  // Readers quote a text cell whole ("unknown camera '...'"): a 10 MB cell stays 80 characters.
  return InputError({path_, lines_[row], index ? static_cast<int>(*index + 1) : 0},
                    "column '" + column + "': " +
                        (index ? WithTextShortened(what, rows_[row][*index]) : what),
                    hint);
}

const std::string& CsvTable::Cell(size_t row, const std::string& column) const {
  const auto index = ColumnIndex(column);
  if (!index) RequireColumns({column});
  return rows_[row][*index];
}

bool CsvTable::HasValue(size_t row, const std::string& column) const {
  return HasColumn(column) && !Cell(row, column).empty();
}

std::string CsvTable::Text(size_t row, const std::string& column) const {
  const std::string& cell = Cell(row, column);
  if (cell.empty()) throw Error(row, column, "empty cell", "Fill in a value");
  return cell;
}

double CsvTable::Number(size_t row, const std::string& column) const {
  const std::string& cell = Cell(row, column);
  if (cell.empty()) throw Error(row, column, "empty cell", "Fill in a number");
  // The whole cell as a decimal number, or nothing: std::from_chars reads no hexadecimal and no
  // locale, and a cell with a NUL byte or anything after the number is refused whole (strtod
  // read "2\0 42.29" as 2 and "0x1p8" as 256).
  const char* first = cell.data() + (cell[0] == '+' ? 1 : 0);
  const char* last = cell.data() + cell.size();
  double value = 0.0;
  const auto [end, error] = std::from_chars(first, last, value);
  if (error == std::errc::result_out_of_range) {
    throw Error(row, column, "'" + QuotedShort(cell) + "' is beyond the range of a number",
                "Write the value in the file's units");
  }
  if (error != std::errc() || end != last || first == last) {
    throw Error(row, column, "'" + QuotedShort(cell) + "' is not a number",
                "Write a plain decimal number");
  }
  if (!std::isfinite(value)) {
    throw Error(row, column, "'" + QuotedShort(cell) + "' is not a finite number",
                "Remove the row or replace the value with a measurement");
  }
  return value;
}

int CsvTable::Integer(size_t row, const std::string& column) const {
  const double value = Number(row, column);
  if (value != std::floor(value) || std::fabs(value) > 2e9) {
    throw Error(row, column, "'" + QuotedShort(Cell(row, column)) + "' is not a whole number",
                "Write a whole number");
  }
  return static_cast<int>(value);
}

std::optional<double> CsvTable::OptionalNumber(size_t row, const std::string& column) const {
  if (!HasValue(row, column)) return std::nullopt;
  return Number(row, column);
}

}  // namespace cellmetry
