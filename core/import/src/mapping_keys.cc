// The small readers of a mapping's keys (mapping_keys.h).
#include "mapping_keys.h"

#include <cmath>
#include <tuple>

#include "cellmetry/basics/text.h"

namespace cellmetry::import_keys {

std::string OneOf(const ConfigNode& node, const std::vector<std::string>& words,
                  const std::string& what) {
  const std::string value = node.AsString();
  for (const auto& w : words) {
    if (w == value) return value;
  }
  const std::string nearest = NearestWord(value, words);
  throw node.Error(
      "unknown " + what + " '" + value + "'",
      (nearest.empty() ? "" : "Did you mean '" + nearest + "'? ") + "Known: " + Join(words));
}

ConfigNode Required(const ConfigNode& node, const std::string& key, const std::string& hint) {
  if (!node.Has(key)) throw node.Error("missing key '" + key + "'", hint);
  return node[key];
}

double LengthToMm(const ConfigNode& node) {
  return OneOf(node, {"mm", "m"}, "length unit") == "m" ? 1000.0 : 1.0;
}

double AngleToRad(const ConfigNode& node) {
  return OneOf(node, {"rad", "deg"}, "angle unit") == "deg" ? M_PI / 180.0 : 1.0;
}

ColumnRef Column(const ConfigNode& node) {
  if (node.IsMap()) {
    node.ExpectKeys({"table", "column"});
    return ColumnOfMap(node, "Write {table: TABLE, column: NAME}, or the column's name alone");
  }
  if (!node.IsScalar() || node.AsString().empty()) {
    throw node.Error("expected a column name",
                     "Write the column's name as the table's header has it");
  }
  return {node.AsString(), node.location(), ""};
}

ColumnRef ColumnOfMap(const ConfigNode& node, const std::string& hint) {
  const ConfigNode column = Required(node, "column", hint);
  if (!column.IsScalar() || column.AsString().empty()) {
    throw column.Error("expected a column name",
                       "Write the column's name as the table's header has it");
  }
  ColumnRef ref{column.AsString(), column.location(), ""};
  if (node.Has("table")) {
    ref.table = node["table"].AsString();
    if (ref.table.empty()) throw node["table"].Error("expected a table's name", hint);
  }
  return ref;
}

std::vector<ColumnRef> Columns(const ConfigNode& node, const std::vector<std::string>& names) {
  if (!node.IsSequence() || node.Elements().size() != names.size()) {
    throw node.Error(
        "expected " + std::to_string(names.size()) + " column names",
        "List the columns of " + Join(names) + ", in this order: [" + Join(names) + "]");
  }
  std::vector<ColumnRef> columns;
  for (const auto& element : node.Elements()) columns.push_back(Column(element));
  return columns;
}

FactSpec ReadFact(const ConfigNode& node, const std::vector<std::string>& units,
                  const std::vector<std::pair<double, double>>& factors) {
  FactSpec fact;
  if (!node.IsMap()) {
    fact.column = Column(node);
    return fact;
  }
  node.ExpectKeys({"table", "column", "unit"});
  fact.column = ColumnOfMap(node, "Name the column: {column: NAME, unit: " + units.front() + "}");
  if (node.Has("unit")) {
    const std::string unit = OneOf(node["unit"], units, "unit");
    for (size_t i = 0; i < units.size(); ++i) {
      if (units[i] == unit) std::tie(fact.scale, fact.offset) = factors[i];
    }
  }
  return fact;
}

}  // namespace cellmetry::import_keys
