// The small readers ReadImportMapping is made of, shared by the files that read its parts:
// import_mapping.cc (robot, targets, observations, facts), mapping_tables.cc (the tables and
// their join) and mapping_uncertainty.cc (an observation's uncertainties). Each refuses what it
// does not understand at the mapping's line and column, with what to write instead.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/import/import_mapping.h"

namespace cellmetry::import_keys {

// A word from a fixed list, refused with the nearest one and the whole list.
std::string OneOf(const ConfigNode& node, const std::vector<std::string>& words,
                  const std::string& what);

// A required key, refused with what it is for.
ConfigNode Required(const ConfigNode& node, const std::string& key, const std::string& hint);

double LengthToMm(const ConfigNode& node);  // mm | m
double AngleToRad(const ConfigNode& node);  // rad | deg

// A column: `NAME` (in whichever table has it; `TABLE.NAME` may say which) or
// {table: TABLE, column: NAME}.
ColumnRef Column(const ConfigNode& node);
// The `column:` (and `table:`) keys of a map that names a column among other keys.
ColumnRef ColumnOfMap(const ConfigNode& node, const std::string& hint);

// A list of exactly `names.size()` columns (`names` say what each one is, for the message).
std::vector<ColumnRef> Columns(const ConfigNode& node, const std::vector<std::string>& names);

// A column with its unit: `NAME` (already in the first unit) or {column: NAME, unit: U}, the
// unit one of `units`, converted by the matching (scale, offset) of `factors`.
FactSpec ReadFact(const ConfigNode& node, const std::vector<std::string>& units,
                  const std::vector<std::pair<double, double>>& factors);

// An observation entry's position_uncertainty: and rotation_sigma:, once its pose columns are
// read (mapping_uncertainty.cc).
void ReadUncertainties(const ConfigNode& node, ObservationSpec* spec);

// table: or tables: (with join:), into m->tables and m->join (mapping_tables.cc).
void ReadTables(const ConfigNode& root, ImportMapping* m);

}  // namespace cellmetry::import_keys
