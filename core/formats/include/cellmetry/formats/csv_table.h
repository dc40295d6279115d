// CSV tables read with their line numbers, for error messages.
//
// The recording files are plain numeric CSV with a header row. Every cell access names the file,
// line and column when the cell is missing, not a number, or not finite, so a user can open the
// file at that spot. Empty cells are allowed where a column is optional (HasValue()).
//
// Two readers share the header and the cells' checks (CsvColumns):
//   CsvTable  the whole table in memory, rows addressed by index: small tables.
//   CsvRows   one data row at a time from the file, for tables of millions of rows (samples.csv,
//             observations.csv): the text never sits in memory as strings, a reader turns each
//             row into its own struct and moves on. It counts the data rows first (one pass
//             over the bytes, no parsing), refuses more than its limit before any is parsed,
//             and reports progress (basics/progress.h) while reading more than
//             kCsvProgressRows rows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/error.h"

namespace cellmetry {

class Progress;

// Tables of more rows than this show their reading's progress; smaller ones read in well under
// a second.
inline constexpr size_t kCsvProgressRows = 100000;

// A table's file and header, and the checked reading of one row's cells by column name.
class CsvColumns {
 public:
  const std::string& path() const { return path_; }
  const std::vector<std::string>& header() const { return header_; }
  bool HasColumn(const std::string& name) const { return ColumnIndex(name).has_value(); }
  // Raises InputError (naming the file and the known columns) when a required column is missing.
  void RequireColumns(const std::vector<std::string>& names) const;
  // Raises InputError for any header column not in `known` (with a "did you mean").
  void RejectUnknownColumns(const std::vector<std::string>& known) const;

 protected:
  std::optional<size_t> ColumnIndex(const std::string& name) const;
  // The cell of `column` in `cells` (a row as long as the header) read at `line`.
  const std::string& Cell(const std::vector<std::string>& cells, const std::string& column) const;
  InputError CellError(int line, const std::vector<std::string>& cells, const std::string& column,
                       const std::string& what, const std::string& hint) const;
  std::string CellText(int line, const std::vector<std::string>& cells,
                       const std::string& column) const;
  double CellNumber(int line, const std::vector<std::string>& cells,
                    const std::string& column) const;
  int CellInteger(int line, const std::vector<std::string>& cells, const std::string& column) const;
  // The row's cells from a line of text, padded to the header's length; an InputError at `line`
  // when it has more cells than the header.
  std::vector<std::string> SplitRow(const std::string& text, int line) const;

  std::string path_;
  std::vector<std::string> header_;
};

class CsvTable : public CsvColumns {
 public:
  // Reads `path`. Raises InputError when the file cannot be opened or has no header row.
  static CsvTable Read(const std::string& path);
  // The same from text already in memory (`path` names it in errors). Empty text gives a table
  // without header or rows; Read refuses that.
  static CsvTable Parse(const std::string& text, const std::string& path);

  size_t num_rows() const { return rows_.size(); }
  // Every data row, each as long as the header (short rows padded with empty cells).
  const std::vector<std::vector<std::string>>& rows() const { return rows_; }
  int line_of(size_t row) const { return lines_[row]; }

  bool HasValue(size_t row, const std::string& column) const;
  std::string Text(size_t row, const std::string& column) const;
  double Number(size_t row, const std::string& column) const;
  int Integer(size_t row, const std::string& column) const;
  std::optional<double> OptionalNumber(size_t row, const std::string& column) const;

  InputError Error(size_t row, const std::string& column, const std::string& what,
                   const std::string& hint) const;

 private:
  std::vector<std::vector<std::string>> rows_;
  std::vector<int> lines_;
};

class CsvRows : public CsvColumns {
 public:
  // Opens `path` (a regular file of at most kMaxTableBytes) and reads its header. Raises
  // InputError when the file cannot be read, has no header row, or has more than `max_rows`
  // data rows; `too_many_hint` says what to do then.
  CsvRows(const std::string& path, size_t max_rows, const std::string& too_many_hint);
  ~CsvRows();
  CsvRows(const CsvRows&) = delete;
  CsvRows& operator=(const CsvRows&) = delete;

  // Data rows in the file (blank and comment lines not counted), known before the first.
  size_t num_rows() const { return num_rows_; }
  // Moves to the next data row; false after the last.
  bool Next();
  // The current row's line in the file.
  int line() const { return line_; }

  bool HasValue(const std::string& column) const;
  std::string Text(const std::string& column) const;
  double Number(const std::string& column) const;
  int Integer(const std::string& column) const;
  std::optional<double> OptionalNumber(const std::string& column) const;

  InputError Error(const std::string& column, const std::string& what,
                   const std::string& hint) const;

 private:
  bool ReadLine(std::string* text);

  std::ifstream in_;
  std::uintmax_t bytes_read_ = 0;
  size_t num_rows_ = 0;
  size_t max_rows_ = 0;
  size_t rows_read_ = 0;
  int line_ = 0;
  std::vector<std::string> cells_;
  std::unique_ptr<Progress> progress_;
};

}  // namespace cellmetry
