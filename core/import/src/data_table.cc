// DataTable (data_table.h): text cells with their place in the file, read as numbers with the
// file's decimal mark.
#include "cellmetry/import/data_table.h"

#include <charconv>
#include <cmath>

#include "cellmetry/formats/quoted_text.h"

namespace cellmetry {

std::optional<double> ParseDecimal(const std::string& text, char decimal, std::string* problem) {
  problem->clear();
  size_t begin = text.find_first_not_of(" \t");
  size_t end = text.find_last_not_of(" \t");
  if (begin == std::string::npos) {
    *problem = "the cell is empty";
    return std::nullopt;
  }
  std::string number = text.substr(begin, end - begin + 1);
  if (decimal == ',') {
    if (number.find('.') != std::string::npos) {
      *problem = "'" + QuotedShort(number) + "' has a '.' but this table's decimal mark is ','";
      return std::nullopt;
    }
    for (char& c : number) {
      if (c == ',') c = '.';
    }
  }
  if (!number.empty() && number[0] == '+') number.erase(0, 1);
  double value = 0.0;
  const char* first = number.data();
  const char* last = number.data() + number.size();
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec == std::errc::result_out_of_range) {
    *problem = "'" + QuotedShort(text) + "' is beyond the range of a number";
    return std::nullopt;
  }
  if (ec != std::errc() || ptr != last || number.empty()) {
    *problem = "'" + QuotedShort(text) + "' is not a number";
    return std::nullopt;
  }
  if (!std::isfinite(value)) {
    *problem = "'" + QuotedShort(text) + "' is not a finite number";
    return std::nullopt;
  }
  return value;
}

std::optional<size_t> DataTable::ColumnIndex(const std::string& name) const {
  for (size_t i = 0; i < columns_.size(); ++i) {
    if (columns_[i] == name) return i;
  }
  return std::nullopt;
}

double DataTable::Number(size_t row, size_t column) const {
  std::string problem;
  const std::optional<double> value = ParseDecimal(cells_[row][column], decimal_, &problem);
  if (value) return *value;
  std::string hint = "Write a plain decimal number";
  if (cells_[row][column].empty()) {
    hint = "Fill in the number, or leave every cell of this observation empty when it was not seen";
  } else if (decimal_ == '.' && cells_[row][column].find(',') != std::string::npos) {
    hint = "If the file writes decimal commas, say so in the mapping: table: {decimal: \",\"}";
  } else if (decimal_ == ',') {
    hint =
        "Write the number with a decimal comma and no thousands separators, as the mapping "
        "says (table: {decimal: \",\"})";
  }
  throw Error(row, column, problem, hint);
}

ClockTime DataTable::DateTime(size_t row, size_t column, const std::string& format) const {
  std::string problem;
  if (const std::optional<ClockTime> t = ParseDateTime(cells_[row][column], format, &problem)) {
    return *t;
  }
  if (cells_[row][column].empty()) problem = "the cell is empty";
  throw Error(row, column, problem,
              "Fix the cell, or write the format its column has in the mapping's time: {format: "
              "...}");
}

SourceLocation DataTable::Where(size_t row, size_t column) const {
  return {path_, lines_[row], positions_[row][column]};
}

SourceLocation DataTable::HeaderWhere(size_t column) const { return header_where_[column]; }

InputError DataTable::Error(size_t row, size_t column, const std::string& what,
                            const std::string& hint) const {
  // Readers quote a cell whole: a 10 MB cell stays 80 characters in the one line.
  return InputError(
      Where(row, column),
      "column '" + QuotedShort(columns_[column]) + "' of data row " + std::to_string(row + 1) +
          ": " + WithTextShortened(WithTextShortened(what, cells_[row][column]), columns_[column]),
      hint);
}

size_t DataTable::AddColumn(const std::string& name, int header_line, int header_column) {
  columns_.push_back(name);
  header_where_.push_back({path_, header_line, header_column});
  for (auto& row : cells_) row.emplace_back();
  for (auto& row : positions_) row.push_back(0);
  return columns_.size() - 1;
}

void DataTable::AddRow(std::vector<std::string> cells, int line, std::vector<int> positions) {
  cells.resize(columns_.size());
  positions.resize(columns_.size(), 0);
  cells_.push_back(std::move(cells));
  lines_.push_back(line);
  positions_.push_back(std::move(positions));
}

}  // namespace cellmetry
