// ReadJsonLinesTable (data_table.h): one JSON object per line, nested objects and arrays
// flattened into columns (pose.t[0]), numbers kept to the last digit.
#include <charconv>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "cellmetry/formats/input_file.h"
#include "cellmetry/formats/strict_json.h"
#include "cellmetry/import/data_table.h"

namespace cellmetry {
namespace {

std::string NumberText(const nlohmann::ordered_json& value) {
  if (value.is_number_integer()) {
    return value.is_number_unsigned() ? std::to_string(value.get<unsigned long long>())
                                      : std::to_string(value.get<long long>());
  }
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof(buffer), value.get<double>()).ptr;
  return std::string(buffer, end);
}

// Every scalar under `value` as (column name, text), objects as a.b, arrays as a[0].
void Flatten(const nlohmann::ordered_json& value, const std::string& name,
             std::vector<std::pair<std::string, std::string>>* out) {
  if (value.is_object()) {
    for (const auto& [key, child] : value.items()) {
      Flatten(child, name.empty() ? key : name + "." + key, out);
    }
  } else if (value.is_array()) {
    for (size_t i = 0; i < value.size(); ++i) {
      Flatten(value[i], name + "[" + std::to_string(i) + "]", out);
    }
  } else if (value.is_number()) {
    out->emplace_back(name, NumberText(value));
  } else if (value.is_string()) {
    out->emplace_back(name, value.get<std::string>());
  } else if (value.is_boolean()) {
    out->emplace_back(name, value.get<bool>() ? "true" : "false");
  } else {
    out->emplace_back(name, "");  // null
  }
}

// The 1-based character where the value of top-level `key` starts on `line` (0 if not found).
int ValueColumn(const std::string& line, const std::string& key) {
  const std::string quoted = "\"" + key + "\"";
  for (size_t at = line.find(quoted); at != std::string::npos; at = line.find(quoted, at + 1)) {
    size_t i = at + quoted.size();
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i >= line.size() || line[i] != ':') continue;
    ++i;
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    return static_cast<int>(i) + 1;
  }
  return 0;
}

std::string TopKey(const std::string& column) {
  return column.substr(0, column.find_first_of(".["));
}

// The number nlohmann names in "number overflow parsing '1e400'", and where it is on `line`.
std::pair<std::string, int> OverflowingNumber(const std::string& message, const std::string& line) {
  const size_t open = message.find('\'');
  const size_t close = message.rfind('\'');
  if (open == std::string::npos || close <= open) return {"", 0};
  const std::string number = message.substr(open + 1, close - open - 1);
  const size_t at = line.find(number);
  const std::string quoted = number.size() > 80 ? number.substr(0, 77) + "..." : number;
  return {quoted, at == std::string::npos ? 0 : static_cast<int>(at) + 1};
}

}  // namespace

DataTable ReadJsonLinesTable(const std::string& path) {
  const char* const where_hint =
      "Check 'table:' in the mapping (a path relative to the mapping file)";
  RequireRegularFile(path, kMaxTableBytes, where_hint);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, 0, 0}, "cannot open the table", where_hint);
  DataTable table(path, "JSON lines", '.');
  std::map<std::string, size_t> index;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line_number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    nlohmann::ordered_json object;
    try {
      object = ParseStrictJson<nlohmann::ordered_json>(line);
    } catch (const nlohmann::json::parse_error& e) {
      throw InputError({path, line_number, static_cast<int>(e.byte)}, "not valid JSON",
                       "Write one JSON object per line: {\"q1\": 0.5, ...}");
    } catch (const nlohmann::json::out_of_range& e) {
      // The one range error parsing raises: a number beyond a double (1e400).
      const auto [number, column] = OverflowingNumber(e.what(), line);
      throw InputError({path, line_number, column},
                       "'" + number + "' is beyond the range of a number",
                       "Write the value in the units the mapping declares");
    } catch (const StrictJsonError& e) {
      throw InputError({path, line_number, 0}, e.what, e.hint);
    }
    if (!object.is_object()) {
      throw InputError({path, line_number, 1}, "the line is JSON but not an object",
                       "Write one JSON object per line: {\"q1\": 0.5, ...}");
    }
    std::vector<std::pair<std::string, std::string>> cells;
    Flatten(object, "", &cells);
    std::vector<std::string> row(table.columns().size());
    std::vector<int> positions(table.columns().size(), 0);
    std::map<std::string, int> key_columns;
    for (auto& [name, text] : cells) {
      auto it = index.find(name);
      if (it == index.end()) {
        it =
            index.emplace(name, table.AddColumn(name, line_number, ValueColumn(line, TopKey(name))))
                .first;
        row.emplace_back();
        positions.push_back(0);
      }
      const std::string top = TopKey(name);
      if (!key_columns.count(top)) key_columns[top] = ValueColumn(line, top);
      row[it->second] = std::move(text);
      positions[it->second] = key_columns[top];
    }
    table.AddRow(std::move(row), line_number, std::move(positions));
  }
  if (table.num_rows() == 0) {
    throw InputError({path, 1, 0}, "the table is empty", "Write one JSON object per line");
  }
  return table;
}

}  // namespace cellmetry
