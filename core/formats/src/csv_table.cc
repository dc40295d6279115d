// CSV tables (csv_table.h): a CSV file read with its line numbers, whole (CsvTable) or one row
// at a time (CsvRows), so that a missing, non-numeric or non-finite cell is an InputError naming
// its file, line and column.
#include "cellmetry/formats/csv_table.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "cellmetry/basics/progress.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/input_file.h"
#include "cellmetry/formats/quoted_text.h"

namespace cellmetry {
namespace {

constexpr char kByteOrderMark[] = "\xEF\xBB\xBF";

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

// A line that holds no row: blank, or a comment ('#' first).
bool SkippedLine(const std::string& line) { return Trim(line).empty() || line[0] == '#'; }

// Lines that hold a row or the header in the file at `path` (the same lines SkippedLine keeps),
// counted in one pass over the bytes without parsing: a limit on rows is checked in a fraction
// of a second, before the work it bounds. Stops counting beyond `max_bytes`.
size_t CountContentLines(const std::string& path, std::uintmax_t max_bytes) {
  std::ifstream in(path, std::ios::binary);
  size_t lines = 0;
  bool at_start = true, comment = false, content = false;
  std::vector<char> buffer(size_t{1} << 20);
  std::uintmax_t total = 0;
  // A byte-order mark alone on the first line leaves nothing there once it is taken off.
  char mark[3] = {};
  if (!in.read(mark, 3) || std::string(mark, 3) != kByteOrderMark) {
    in.clear();
    in.seekg(0);
  }
  while (total <= max_bytes &&
         (in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) || in.gcount() > 0)) {
    const size_t n = static_cast<size_t>(in.gcount());
    total += n;
    for (size_t i = 0; i < n; ++i) {
      const char c = buffer[i];
      if (c == '\n') {
        lines += content && !comment;
        at_start = true;
        comment = content = false;
        continue;
      }
      if (at_start && c == '#') comment = true;
      at_start = false;
      if (c != ' ' && c != '\t' && c != '\r') content = true;
    }
  }
  return lines + (content && !comment);
}

std::string FileName(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace

// --- CsvColumns ---------------------------------------------------------------------------

std::optional<size_t> CsvColumns::ColumnIndex(const std::string& name) const {
  for (size_t i = 0; i < header_.size(); ++i) {
    if (header_[i] == name) return i;
  }
  return std::nullopt;
}

void CsvColumns::RequireColumns(const std::vector<std::string>& names) const {
  for (const auto& name : names) {
    if (HasColumn(name)) continue;
    std::string present;
    for (const auto& h : header_) present += (present.empty() ? "" : ",") + QuotedShort(h);
    throw InputError({path_, 1, 0}, "missing column '" + name + "'",
                     "The header must name it; the header is: " + present);
  }
}

void CsvColumns::RejectUnknownColumns(const std::vector<std::string>& known) const {
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

const std::string& CsvColumns::Cell(const std::vector<std::string>& cells,
                                    const std::string& column) const {
  const auto index = ColumnIndex(column);
  if (!index) RequireColumns({column});
  return cells[*index];
}

InputError CsvColumns::CellError(int line, const std::vector<std::string>& cells,
                                 const std::string& column, const std::string& what,
                                 const std::string& hint) const {
  const auto index = ColumnIndex(column);
  // Readers quote a text cell whole ("unknown camera '...'"): a 10 MB cell stays 80 characters.
  return InputError(
      {path_, line, index ? static_cast<int>(*index + 1) : 0},
      "column '" + column + "': " + (index ? WithTextShortened(what, cells[*index]) : what), hint);
}

std::string CsvColumns::CellText(int line, const std::vector<std::string>& cells,
                                 const std::string& column) const {
  const std::string& cell = Cell(cells, column);
  if (cell.empty()) throw CellError(line, cells, column, "empty cell", "Fill in a value");
  return cell;
}

double CsvColumns::CellNumber(int line, const std::vector<std::string>& cells,
                              const std::string& column) const {
  const std::string& cell = Cell(cells, column);
  if (cell.empty()) throw CellError(line, cells, column, "empty cell", "Fill in a number");
  // The whole cell as a decimal number, or nothing: std::from_chars reads no hexadecimal and no
  // locale, and a cell with a NUL byte or anything after the number is refused whole (strtod
  // read "2\0 42.29" as 2 and "0x1p8" as 256).
  const char* first = cell.data() + (cell[0] == '+' ? 1 : 0);
  const char* last = cell.data() + cell.size();
  double value = 0.0;
  const auto [end, error] = std::from_chars(first, last, value);
  if (error == std::errc::result_out_of_range) {
    throw CellError(line, cells, column,
                    "'" + QuotedShort(cell) + "' is beyond the range of a number",
                    "Write the value in the file's units");
  }
  if (error != std::errc() || end != last || first == last) {
    throw CellError(line, cells, column, "'" + QuotedShort(cell) + "' is not a number",
                    "Write a plain decimal number");
  }
  if (!std::isfinite(value)) {
    throw CellError(line, cells, column, "'" + QuotedShort(cell) + "' is not a finite number",
                    "Remove the row or replace the value with a measurement");
  }
  return value;
}

int CsvColumns::CellInteger(int line, const std::vector<std::string>& cells,
                            const std::string& column) const {
  const double value = CellNumber(line, cells, column);
  if (value != std::floor(value) || std::fabs(value) > 2e9) {
    throw CellError(line, cells, column,
                    "'" + QuotedShort(Cell(cells, column)) + "' is not a whole number",
                    "Write a whole number");
  }
  return static_cast<int>(value);
}

std::vector<std::string> CsvColumns::SplitRow(const std::string& text, int line) const {
  auto cells = SplitCsvLine(text);
  if (cells.size() > header_.size()) {
    throw InputError({path_, line, 0},
                     "row has " + std::to_string(cells.size()) + " cells but the header has " +
                         std::to_string(header_.size()),
                     "Remove the extra cells or add their column to the header");
  }
  cells.resize(header_.size());  // short rows: trailing optional cells left empty
  return cells;
}

// --- CsvTable ------------------------------------------------------------------------------

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
    if (line_number == 1 && line.rfind(kByteOrderMark, 0) == 0) line.erase(0, 3);
    if (SkippedLine(line)) continue;
    if (table.header_.empty()) {
      table.header_ = SplitCsvLine(line);
      continue;
    }
    table.rows_.push_back(table.SplitRow(line, line_number));
    table.lines_.push_back(line_number);
  }
  return table;
}

InputError CsvTable::Error(size_t row, const std::string& column, const std::string& what,
                           const std::string& hint) const {
  return CellError(lines_[row], rows_[row], column, what, hint);
}

bool CsvTable::HasValue(size_t row, const std::string& column) const {
  return HasColumn(column) && !Cell(rows_[row], column).empty();
}

std::string CsvTable::Text(size_t row, const std::string& column) const {
  return CellText(lines_[row], rows_[row], column);
}

double CsvTable::Number(size_t row, const std::string& column) const {
  return CellNumber(lines_[row], rows_[row], column);
}

int CsvTable::Integer(size_t row, const std::string& column) const {
  return CellInteger(lines_[row], rows_[row], column);
}

std::optional<double> CsvTable::OptionalNumber(size_t row, const std::string& column) const {
  if (!HasValue(row, column)) return std::nullopt;
  return Number(row, column);
}

// --- CsvRows -------------------------------------------------------------------------------

CsvRows::CsvRows(const std::string& path, size_t max_rows, const std::string& too_many_hint) {
  path_ = path;
  RequireRegularFile(path, kMaxTableBytes, "Check that the file exists");
  const size_t content_lines = CountContentLines(path, kMaxTableBytes);
  num_rows_ = content_lines > 0 ? content_lines - 1 : 0;  // the first is the header
  max_rows_ = max_rows;
  if (num_rows_ > max_rows) {
    throw InputError({path, 0, 0},
                     "has " + std::to_string(num_rows_) + " rows, more than the " +
                         std::to_string(max_rows) + " cellmetry reads from a table of this kind",
                     too_many_hint);
  }
  in_.open(path, std::ios::binary);
  if (!in_) throw InputError({path, 0, 0}, "cannot open file", "Check the file's permissions");
  std::string text;
  while (header_.empty() && ReadLine(&text)) {
    // A UTF-8 byte-order mark (spreadsheet exports write one) is not part of the first column.
    if (line_ == 1 && text.rfind(kByteOrderMark, 0) == 0) text.erase(0, 3);
    if (!SkippedLine(text)) header_ = SplitCsvLine(text);
  }
  if (header_.empty()) {
    throw InputError({path, 1, 0}, "file is empty", "The first line must be the column header");
  }
  if (num_rows_ > kCsvProgressRows) {
    progress_ = std::make_unique<Progress>("reading " + FileName(path) + " rows",
                                           static_cast<int>(num_rows_));
  }
}

CsvRows::~CsvRows() = default;

bool CsvRows::ReadLine(std::string* text) {
  if (!std::getline(in_, *text)) return false;
  ++line_;
  bytes_read_ += text->size() + 1;
  // A file that grows while it is read stops at the limit all the same.
  if (bytes_read_ > kMaxTableBytes + 1) {
    throw InputError({path_, line_, 0}, "grew beyond its size limit while being read",
                     "Wait until whatever writes it has finished, then run again");
  }
  return true;
}

bool CsvRows::Next() {
  std::string text;
  while (ReadLine(&text)) {
    if (SkippedLine(text)) continue;
    // A file that grows after its rows were counted stops at the limit all the same.
    if (++rows_read_ > max_rows_) {
      throw InputError({path_, line_, 0},
                       "grew beyond " + std::to_string(max_rows_) + " rows while being read",
                       "Wait until whatever writes it has finished, then run again");
    }
    cells_ = SplitRow(text, line_);
    if (progress_) progress_->Advance();
    return true;
  }
  return false;
}

bool CsvRows::HasValue(const std::string& column) const {
  return HasColumn(column) && !Cell(cells_, column).empty();
}

std::string CsvRows::Text(const std::string& column) const {
  return CellText(line_, cells_, column);
}

double CsvRows::Number(const std::string& column) const {
  return CellNumber(line_, cells_, column);
}

int CsvRows::Integer(const std::string& column) const { return CellInteger(line_, cells_, column); }

std::optional<double> CsvRows::OptionalNumber(const std::string& column) const {
  if (!HasValue(column)) return std::nullopt;
  return Number(column);
}

InputError CsvRows::Error(const std::string& column, const std::string& what,
                          const std::string& hint) const {
  return CellError(line_, cells_, column, what, hint);
}

}  // namespace cellmetry
