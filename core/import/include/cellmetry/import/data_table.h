// DataTable: a user's table (a spreadsheet's CSV export, a logger's JSON lines) as text cells,
// each knowing where it stands in its file, so that every complaint about a cell reads
// `file:line:column: error: column 'q3' of data row 12: 'abc' is not a number. ...`.
//
// Contract:
//  - The first non-blank CSV record is the header; JSON lines name their columns in every object
//    (the header is every key in order of first appearance). Column names are unique.
//  - Cells are text; Number() reads one as a finite decimal number with the file's decimal mark
//    and raises InputError at the cell otherwise. An empty cell is a cell with no value.
//  - Locations: the line the row starts on; the column is the field's position in the record
//    for CSV (a spreadsheet's column number, 1 = A) and the character where the value starts for
//    JSON lines.
//
// CSV (ReadCsvTable): UTF-8 with or without a byte-order mark (UTF-16 is refused with what to
// do; bytes that are not UTF-8 are refused at their field, with the encoding to state), or an
// 8-bit encoding the dialect names, converted to UTF-8 before anything else; fields separated
// by ',' ';' or tab (`separator`, or detected from the header: the one of them it holds most
// of, outside quotes); "quoted" fields may hold the separator, line breaks and doubled quotes
// (""); decimal mark '.' or ',' (a ',' decimal needs another separator). Blank lines are
// skipped; a row shorter than the header leaves its last cells empty.
//
// JSON lines (ReadJsonLinesTable): one JSON object per line. Nested objects and arrays are
// flattened: {"pose": {"t": [1, 2, 3]}} gives the columns pose.t[0], pose.t[1], pose.t[2].
// Numbers keep every digit; null is an empty cell.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/error.h"
#include "cellmetry/import/date_time.h"
#include "cellmetry/import/text_encoding.h"

namespace cellmetry {

struct CsvDialect {
  char separator = 0;                           // ',', ';' or '\t'; 0: detect from the header line
  char decimal = '.';                           // '.' or ','
  TextEncoding encoding = TextEncoding::kUtf8;  // the file's; cells and names become UTF-8
};

class DataTable {
 public:
  DataTable(std::string path, std::string kind, char decimal)
      : path_(std::move(path)), kind_(std::move(kind)), decimal_(decimal) {}

  const std::string& path() const { return path_; }
  const std::string& kind() const { return kind_; }  // "CSV" or "JSON lines", for messages
  char decimal() const { return decimal_; }
  const std::vector<std::string>& columns() const { return columns_; }
  size_t num_rows() const { return cells_.size(); }

  std::optional<size_t> ColumnIndex(const std::string& name) const;
  const std::string& Cell(size_t row, size_t column) const { return cells_[row][column]; }
  bool IsEmpty(size_t row, size_t column) const { return cells_[row][column].empty(); }
  // The cell as a finite number; InputError at the cell when it is empty or is not one.
  double Number(size_t row, size_t column) const;
  // The cell as a date and time in `format` (date_time.h); InputError at the cell when it is
  // empty or does not read so.
  ClockTime DateTime(size_t row, size_t column, const std::string& format) const;

  SourceLocation Where(size_t row, size_t column) const;
  SourceLocation HeaderWhere(size_t column) const;
  // An InputError at the cell: "column 'NAME' of data row N: WHAT".
  InputError Error(size_t row, size_t column, const std::string& what,
                   const std::string& hint) const;

  // Building (the readers): a column, then rows of cells with their line and columns.
  size_t AddColumn(const std::string& name, int header_line, int header_column);
  void AddRow(std::vector<std::string> cells, int line, std::vector<int> positions);

 private:
  std::string path_;
  std::string kind_;
  char decimal_;
  std::vector<std::string> columns_;
  std::vector<SourceLocation> header_where_;
  std::vector<std::vector<std::string>> cells_;
  std::vector<int> lines_;
  std::vector<std::vector<int>> positions_;
};

// `text` as a finite decimal number written with `decimal` as its decimal mark (surrounding
// spaces and a leading '+' allowed). None, with the reason in `problem`, otherwise.
std::optional<double> ParseDecimal(const std::string& text, char decimal, std::string* problem);

// Reads a CSV file (see above). InputError when it cannot be read, is empty, is UTF-16, is not
// UTF-8 and the dialect names no other encoding, has an unclosed quote, a duplicate column name
// or a row longer than its header.
DataTable ReadCsvTable(const std::string& path, const CsvDialect& dialect);

// Reads a JSON-lines file (see above). InputError at the line and character of a syntax error,
// or at a line that is not one JSON object.
DataTable ReadJsonLinesTable(const std::string& path);

}  // namespace cellmetry
