// CsvTable: a comma-separated table read with its line numbers, for error messages.
//
// The recording files are plain numeric CSV with a header row. Every cell access names the file,
// line and column when the cell is missing, not a number, or not finite, so a user can open the
// file at that spot. Empty cells are allowed where a column is optional (HasValue()).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/error.h"

namespace cellmetry {

class CsvTable {
 public:
  // Reads `path`. Raises InputError when the file cannot be opened or has no header row.
  static CsvTable Read(const std::string& path);
  // The same from text already in memory (`path` names it in errors). Empty text gives a table
  // without header or rows; Read refuses that.
  static CsvTable Parse(const std::string& text, const std::string& path);

  const std::string& path() const { return path_; }
  const std::vector<std::string>& header() const { return header_; }
  size_t num_rows() const { return rows_.size(); }
  // Every data row, each as long as the header (short rows padded with empty cells).
  const std::vector<std::vector<std::string>>& rows() const { return rows_; }
  int line_of(size_t row) const { return lines_[row]; }

  bool HasColumn(const std::string& name) const { return ColumnIndex(name).has_value(); }
  // Raises InputError (naming the file and the known columns) when a required column is missing.
  void RequireColumns(const std::vector<std::string>& names) const;
  // Raises InputError for any header column not in `known` (with a "did you mean").
  void RejectUnknownColumns(const std::vector<std::string>& known) const;

  bool HasValue(size_t row, const std::string& column) const;
  std::string Text(size_t row, const std::string& column) const;
  double Number(size_t row, const std::string& column) const;
  int Integer(size_t row, const std::string& column) const;
  std::optional<double> OptionalNumber(size_t row, const std::string& column) const;

  InputError Error(size_t row, const std::string& column, const std::string& what,
                   const std::string& hint) const;

 private:
  std::optional<size_t> ColumnIndex(const std::string& name) const;
  const std::string& Cell(size_t row, const std::string& column) const;

  std::string path_;
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<int> lines_;
};

}  // namespace cellmetry
