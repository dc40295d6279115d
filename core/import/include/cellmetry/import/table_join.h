// JoinedTable: the tables a mapping names with their rows joined into one row each — a robot's
// log and an instrument's log kept in separate files read as if they were one table — every
// cell still where it stands in its own file, so that a complaint names that file, line and
// column.
//
// Contract:
//  - One table: its rows as they are.
//  - join by row: row i of every table is joined row i. Tables of different lengths are refused
//    at the first row that has no partner, naming both files and their numbers of rows.
//  - join by time: each row of the first table is joined with the row of every other table
//    nearest to it in time (each time column converted to s by its unit). One to one: a row of
//    the first table with no row of another within tolerance_s, a row of another that two rows
//    of the first take as theirs, and one that no row takes are each refused at their time cell,
//    with the nearest candidate and how far it is.
//  - Columns (Find, Bind): a reference that names its table ({table: T, column: C}) is looked
//    up in T; `T.C`, T a table's name, in T; any other name in every table, and it must be in
//    exactly one (a name two tables have is refused: say which). A name matches a header's
//    exactly, or else, when one header's does, once every run of white space in both is a
//    single space (`X [mm]` finds `X  [mm]`). A column found nowhere is refused at the mapping
//    with the nearest name (or the header).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/import/data_table.h"
#include "cellmetry/import/import_mapping.h"

namespace cellmetry {

class JoinedTable {
 public:
  // A column of one of the tables.
  struct Column {
    size_t table = 0;
    size_t column = 0;
  };

  // `tables` in the order of mapping.tables, joined as mapping.join says.
  static JoinedTable Join(const ImportMapping& mapping, std::vector<DataTable> tables);

  size_t num_rows() const { return rows_.size(); }
  const std::vector<DataTable>& tables() const { return tables_; }
  // "readings.csv", or "joints.csv + tracker.csv": the files, for messages.
  std::string FileNames() const;

  std::optional<Column> Find(const ColumnRef& ref) const;
  Column Bind(const ColumnRef& ref) const;  // Find, or InputError at the mapping

  // As DataTable's, at joined row `row` (data_table.h).
  const std::string& Cell(size_t row, Column c) const {
    return At(c).Cell(RowOf(row, c), c.column);
  }
  bool IsEmpty(size_t row, Column c) const { return At(c).IsEmpty(RowOf(row, c), c.column); }
  double Number(size_t row, Column c) const { return At(c).Number(RowOf(row, c), c.column); }
  ClockTime DateTime(size_t row, Column c, const std::string& format) const {
    return At(c).DateTime(RowOf(row, c), c.column, format);
  }
  InputError Error(size_t row, Column c, const std::string& what, const std::string& hint) const {
    return At(c).Error(RowOf(row, c), c.column, what, hint);
  }

 private:
  JoinedTable(std::vector<DataTable> tables, std::vector<std::string> names)
      : tables_(std::move(tables)), names_(std::move(names)) {}
  const DataTable& At(Column c) const { return tables_[c.table]; }
  size_t RowOf(size_t row, Column c) const { return rows_[row][c.table]; }

  void JoinByRow();
  void JoinByTime(const JoinSpec& join);
  // Every column whose header matches `name` in the tables `candidates`, exactly or (not
  // `exact`) with its white space collapsed.
  std::vector<Column> Matches(const std::vector<size_t>& candidates, const std::string& name,
                              bool exact) const;

  std::vector<DataTable> tables_;
  std::vector<std::string> names_;         // as the mapping names them ("" for `table:`)
  std::vector<std::vector<size_t>> rows_;  // joined row -> the row of each table
};

}  // namespace cellmetry
