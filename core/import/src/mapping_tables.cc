// The mapping's tables (mapping_keys.h): `table:` for one, or `tables:` with `join:` for a robot
// log and an instrument log kept in separate files; each with its format, CSV dialect and text
// encoding.
#include <algorithm>
#include <set>

#include "cellmetry/basics/text.h"
#include "mapping_keys.h"

namespace cellmetry::import_keys {
namespace {

// The time units a join's time columns may be in, and their factors to s.
const std::vector<std::string> kTimeUnits = {"s", "ms", "min", "h"};
const std::vector<std::pair<double, double>> kTimeToSeconds = {
    {1.0, 0.0}, {1e-3, 0.0}, {60.0, 0.0}, {3600.0, 0.0}};

// JSON lines by `format:` or by the file's extension; CSV otherwise.
bool IsJsonLines(const std::string& path, const std::string& format_name) {
  if (!format_name.empty()) return format_name == "jsonl";
  const size_t dot = path.find_last_of('.');
  const std::string extension = dot == std::string::npos ? "" : path.substr(dot + 1);
  return extension == "jsonl" || extension == "ndjson" || extension == "json";
}

// One table: its path (relative to the mapping), or {path, format, separator, decimal,
// encoding}.
TableSpec ReadTable(const ConfigNode& node, const std::string& name) {
  TableSpec spec;
  spec.name = name;
  spec.where = node.location();
  if (!node.IsMap()) {
    spec.path = node.ResolvePath(node.AsString());
    spec.json_lines = IsJsonLines(spec.path, "");
    return spec;
  }
  node.ExpectKeys({"path", "format", "separator", "decimal", "encoding"});
  spec.path = node.ResolvePath(Required(node, "path", "Name the table's file").AsString());
  const std::string format_name =
      node.Has("format") ? OneOf(node["format"], {"csv", "jsonl"}, "table format") : "";
  spec.json_lines = IsJsonLines(spec.path, format_name);
  if (node.Has("separator")) {
    const std::string s = OneOf(node["separator"], {",", ";", "tab"}, "separator");
    spec.csv.separator = s == "tab" ? '\t' : s[0];
  }
  if (node.Has("decimal")) {
    spec.csv.decimal = OneOf(node["decimal"], {".", ","}, "decimal mark")[0];
  }
  if (spec.csv.separator && spec.csv.separator == spec.csv.decimal) {
    throw node["decimal"].Error("the separator and the decimal mark are both ','",
                                "A table with decimal commas separates its fields with ';'");
  }
  if (node.Has("encoding")) {
    const ConfigNode encoding = node["encoding"];
    const auto named = TextEncodingNamed(encoding.AsString());
    if (!named) {
      OneOf(encoding, {"utf-8", "latin1", "windows-1252", "cp1252"}, "text encoding");
    }
    spec.csv.encoding = *named;
  }
  if (spec.json_lines) {
    for (const char* key : {"separator", "decimal", "encoding"}) {
      if (node.Has(key)) {
        throw node[key].Error(std::string(key) + " is for CSV tables",
                              "JSON lines are UTF-8 and need no separator or decimal mark: "
                              "remove it");
      }
    }
  }
  return spec;
}

// tables: NAME -> table, two or more, each name a plain word (columns are named TABLE.COLUMN).
void ReadNamedTables(const ConfigNode& tables, ImportMapping* m) {
  tables.ExpectMap();
  for (const auto& name : tables.Keys()) {
    if (name.empty() || name.find_first_of(".,\" \t\n") != std::string::npos) {
      throw tables[name].Error("'" + name + "' cannot name a table",
                               "Choose a plain word without '.' or spaces (robot, tracker): "
                               "columns are named TABLE.COLUMN");
    }
    m->tables.push_back(ReadTable(tables[name], name));
  }
  if (m->tables.size() < 2) {
    throw tables.Error("tables: names " + std::to_string(m->tables.size()) + " table",
                       "Name one table with table: PATH, or two or more under tables: with "
                       "join: saying how their rows belong together");
  }
}

// join: by row, or by time with each table's time column and the tolerance.
void ReadJoin(const ConfigNode& join, ImportMapping* m) {
  join.ExpectMap();
  m->join.where = join.location();
  const std::string by =
      OneOf(Required(join, "by",
                     "Say how rows belong together: by: row (row i of every table is one "
                     "row) or by: time (rows nearest in time)"),
            {"row", "time"}, "join");
  if (by == "row") {
    join.ExpectKeys({"by"});
    m->join.by = JoinKind::kRow;
    return;
  }
  join.ExpectKeys({"by", "columns", "tolerance_s"});
  m->join.by = JoinKind::kTime;
  std::vector<std::string> names;
  for (const auto& t : m->tables) names.push_back(t.name);
  const ConfigNode columns = Required(join, "columns",
                                      "Name each table's time column: columns: {" + names[0] +
                                          ": t, " + names[1] + ": {column: stamp, unit: ms}}");
  columns.ExpectMap();
  for (const auto& key : columns.Keys()) {
    if (std::find(names.begin(), names.end(), key) == names.end()) {
      const std::string nearest = NearestWord(key, names);
      throw columns[key].Error(
          "'" + key + "' is not under tables:",
          (nearest.empty() ? "" : "Did you mean '" + nearest + "'? ") + "Tables: " + Join(names));
    }
  }
  for (const auto& table : m->tables) {
    const ConfigNode column =
        Required(columns, table.name, "Name table " + table.name + "'s time column too");
    FactSpec time = ReadFact(column, kTimeUnits, kTimeToSeconds);
    if (!time.column.table.empty() && time.column.table != table.name) {
      throw column.Error("the time column of " + table.name + " is in its own table",
                         "Leave out table: here");
    }
    time.column.table = table.name;
    m->join.time_s.push_back(time);
  }
  Required(join, "tolerance_s",
           "Say how far apart in time (s) two rows may be and still be one "
           "row, e.g. tolerance_s: 0.01");
  m->join.tolerance_s = join.GetDoubleIn("tolerance_s", 0.0, 0.0, 1e6,
                                         "The largest time difference (s) between joined rows");
}

}  // namespace

void ReadTables(const ConfigNode& root, ImportMapping* m) {
  if (root.Has("table") == root.Has("tables")) {
    throw root.Error(root.Has("table") ? "give table: or tables:, not both" : "missing key 'table'",
                     "Name the table to import: table: readings.csv (relative to this file); "
                     "or, for several, tables: {robot: joints.csv, tracker: tracker.csv} with "
                     "join: {by: row}");
  }
  if (root.Has("table")) {
    m->tables.push_back(ReadTable(root["table"], ""));
    if (root.Has("join")) {
      throw root["join"].Error("join: is for several tables",
                               "Remove it, or name the tables under tables:");
    }
    return;
  }
  ReadNamedTables(root["tables"], m);
  ReadJoin(Required(root, "join",
                    "Say how the tables' rows belong together: join: {by: row} "
                    "or join: {by: time, columns: {...}, tolerance_s: 0.01}"),
           m);
}

}  // namespace cellmetry::import_keys
