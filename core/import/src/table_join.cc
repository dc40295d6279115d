// JoinedTable (table_join.h): several tables' rows joined by number or by time, and the
// mapping's column names found in them.
#include "cellmetry/import/table_join.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <vector>

#include "cellmetry/formats/config_node.h"

namespace cellmetry {
namespace {

std::string FileName(const DataTable& table) {
  return std::filesystem::path(table.path()).filename().string();
}

std::string Seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g s", s);
  return text;
}

// `name` with every run of spaces and tabs one space, and none at either end.
std::string CollapseSpaces(const std::string& name) {
  std::string out;
  for (const char c : name) {
    const bool space = c == ' ' || c == '\t';
    if (space && (out.empty() || out.back() == ' ')) continue;
    out += space ? ' ' : c;
  }
  if (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// "data row 12 (line 13)" of a table.
std::string RowText(const DataTable& table, size_t row) {
  return "data row " + std::to_string(row + 1) + " (line " +
         std::to_string(table.Where(row, 0).line) + ")";
}

// The row numbers of `time_s` in time order (equal times in row order).
std::vector<size_t> TimeOrder(const std::vector<double>& time_s) {
  std::vector<size_t> order(time_s.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return time_s[a] < time_s[b]; });
  return order;
}

// The row nearest in time to `at_s`: the nearer of the two rows either side of it in `order`
// (TimeOrder of `time_s`), the earlier on a tie; none when the table has no rows.
std::optional<size_t> NearestInTime(const std::vector<double>& time_s,
                                    const std::vector<size_t>& order, double at_s) {
  const auto after = std::lower_bound(order.begin(), order.end(), at_s,
                                      [&](size_t i, double v) { return time_s[i] < v; });
  std::optional<size_t> nearest;
  if (after != order.end()) nearest = *after;
  if (after != order.begin() &&
      (!nearest || at_s - time_s[*(after - 1)] <= time_s[*nearest] - at_s)) {
    nearest = *(after - 1);
  }
  return nearest;
}

}  // namespace

JoinedTable JoinedTable::Join(const ImportMapping& mapping, std::vector<DataTable> tables) {
  std::vector<std::string> names;
  for (const auto& spec : mapping.tables) names.push_back(spec.name);
  JoinedTable joined(std::move(tables), std::move(names));
  if (joined.tables_.size() > 1 && mapping.join.by == JoinKind::kTime) {
    joined.JoinByTime(mapping.join);
  } else {
    joined.JoinByRow();
  }
  return joined;
}

std::string JoinedTable::FileNames() const {
  std::string text;
  for (const auto& t : tables_) text += (text.empty() ? "" : " + ") + FileName(t);
  return text;
}

void JoinedTable::JoinByRow() {
  const DataTable& first = tables_.front();
  for (const DataTable& other : tables_) {
    if (other.num_rows() == first.num_rows()) continue;
    const bool other_longer = other.num_rows() > first.num_rows();
    const DataTable& longer = other_longer ? other : first;
    const DataTable& shorter = other_longer ? first : other;
    throw InputError(longer.Where(shorter.num_rows(), 0),
                     FileName(longer) + " has " + std::to_string(longer.num_rows()) +
                         " data rows but " + shorter.path() + " has " +
                         std::to_string(shorter.num_rows()) + ": this row has no partner",
                     "join: {by: row} joins row i of each table; give the tables the same rows "
                     "in the same order, or join them by time");
  }
  rows_.assign(first.num_rows(), std::vector<size_t>(tables_.size()));
  for (size_t r = 0; r < rows_.size(); ++r) std::fill(rows_[r].begin(), rows_[r].end(), r);
}

void JoinedTable::JoinByTime(const JoinSpec& join) {
  // Each table's times in s, and each table's rows in time order.
  std::vector<std::vector<double>> time_s(tables_.size());
  std::vector<Column> time_column(tables_.size());
  for (size_t t = 0; t < tables_.size(); ++t) {
    time_column[t] = Bind(join.time_s[t].column);
    for (size_t r = 0; r < tables_[t].num_rows(); ++r) {
      time_s[t].push_back(tables_[t].Number(r, time_column[t].column) * join.time_s[t].scale +
                          join.time_s[t].offset);
    }
  }
  const DataTable& lead = tables_.front();
  const std::string hint =
      "Rows are joined one to one, each with the row nearest in time: check that the clocks "
      "count from the same moment in the units the join says (columns: {TABLE: {column: C, "
      "unit: ms}}), and that tolerance_s is about half the time between rows";
  rows_.assign(lead.num_rows(), std::vector<size_t>(tables_.size(), 0));
  for (size_t r = 0; r < lead.num_rows(); ++r) rows_[r][0] = r;
  for (size_t t = 1; t < tables_.size(); ++t) {
    const DataTable& other = tables_[t];
    const std::vector<size_t> order = TimeOrder(time_s[t]);
    std::vector<std::optional<size_t>> taken_by(other.num_rows());
    for (size_t r = 0; r < lead.num_rows(); ++r) {
      const double at = time_s[0][r];
      const std::optional<size_t> nearest = NearestInTime(time_s[t], order, at);
      const double gap = nearest ? std::abs(time_s[t][*nearest] - at) : HUGE_VAL;
      if (!nearest || gap > join.tolerance_s) {
        throw lead.Error(r, time_column[0].column,
                         "no row of " + other.path() + " within " + Seconds(join.tolerance_s) +
                             " of " + Seconds(at) +
                             (nearest ? " (the nearest, " + RowText(other, *nearest) + ", is " +
                                            Seconds(gap) + " away)"
                                      : " (it has no rows)"),
                         hint);
      }
      if (taken_by[*nearest]) {
        throw other.Error(*nearest, time_column[t].column,
                          "the nearest row in time to two rows of " + lead.path() + ": " +
                              RowText(lead, *taken_by[*nearest]) + " and " + RowText(lead, r),
                          hint);
      }
      taken_by[*nearest] = r;
      rows_[r][t] = *nearest;
    }
    for (size_t i = 0; i < other.num_rows(); ++i) {
      if (!taken_by[i]) {
        throw other.Error(i, time_column[t].column,
                          "no row of " + lead.path() + " within " + Seconds(join.tolerance_s) +
                              " of " + Seconds(time_s[t][i]) + " took this row as its partner",
                          hint);
      }
    }
  }
}

std::vector<JoinedTable::Column> JoinedTable::Matches(const std::vector<size_t>& candidates,
                                                      const std::string& name, bool exact) const {
  std::vector<Column> found;
  const std::string collapsed = CollapseSpaces(name);
  for (size_t t : candidates) {
    const auto& columns = tables_[t].columns();
    for (size_t c = 0; c < columns.size(); ++c) {
      if (exact ? columns[c] == name : CollapseSpaces(columns[c]) == collapsed) {
        found.push_back({t, c});
      }
    }
  }
  return found;
}

std::optional<JoinedTable::Column> JoinedTable::Find(const ColumnRef& ref) const {
  // (tables to look in, name) readings of the reference.
  std::vector<std::pair<std::vector<size_t>, std::string>> readings;
  if (!ref.table.empty()) {
    const auto named = std::find(names_.begin(), names_.end(), ref.table);
    if (named == names_.end()) {
      const std::string nearest = NearestWord(ref.table, names_);
      throw InputError(ref.where, "no table '" + ref.table + "' under tables:",
                       nearest.empty() ? "Name one of the tables the mapping reads"
                                       : "Did you mean '" + nearest + "'?");
    }
    readings.push_back({{static_cast<size_t>(named - names_.begin())}, ref.name});
  } else {
    std::vector<size_t> every(tables_.size());
    for (size_t t = 0; t < every.size(); ++t) every[t] = t;
    readings.push_back({every, ref.name});
    for (size_t t = 0; t < names_.size(); ++t) {
      const std::string prefix = names_[t] + ".";
      if (!names_[t].empty() && ref.name.rfind(prefix, 0) == 0) {
        readings.push_back({{t}, ref.name.substr(prefix.size())});
      }
    }
  }
  for (const bool exact : {true, false}) {
    std::vector<Column> found;
    for (const auto& [candidates, name] : readings) {
      for (const Column& c : Matches(candidates, name, exact)) found.push_back(c);
    }
    if (found.size() == 1) return found.front();
    if (found.size() > 1) {
      const Column& a = found[0];
      const Column& b = found[1];
      throw InputError(
          ref.where,
          "column '" + ref.name + "' could be '" + tables_[a.table].columns()[a.column] + "' of " +
              FileName(tables_[a.table]) + " or '" + tables_[b.table].columns()[b.column] +
              "' of " + FileName(tables_[b.table]),
          names_[a.table].empty()
              ? "Write the column's name exactly as the header has it"
              : "Say which: " + names_[a.table] + "." + tables_[a.table].columns()[a.column] +
                    " or {table: " + names_[a.table] + ", column: ...}");
    }
  }
  return std::nullopt;
}

JoinedTable::Column JoinedTable::Bind(const ColumnRef& ref) const {
  if (const auto found = Find(ref)) return *found;
  std::vector<std::string> every;
  std::string header, files;
  for (size_t t = 0; t < tables_.size(); ++t) {
    if (!ref.table.empty() && names_[t] != ref.table) continue;
    files += (files.empty() ? "" : " or ") + tables_[t].path();
    for (const auto& name : tables_[t].columns()) {
      every.push_back(name);
      if (every.size() <= 40) header += (header.empty() ? "" : ", ") + name;
    }
  }
  if (every.size() > 40) header += ", ...";
  const std::string nearest = NearestWord(ref.name, every);
  throw InputError(
      ref.where,
      "column '" + ref.name + "' is not in the table" +
          (files.find(" or ") == std::string::npos ? " " : "s ") + files,
      nearest.empty() ? "The table's columns are: " + header : "Did you mean '" + nearest + "'?");
}

}  // namespace cellmetry
