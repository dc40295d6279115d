// ImportMapping: the small YAML file (`mapping: cellmetry-import/1`) that says how a user's table
// becomes a cellmetry recording — which columns are the joints, which hold the observed poses of
// which target in which camera and in which convention and units, which rows repeat a pose, and
// which columns are facts (time, temperature, payload). docs/formats.md has every key; in short:
//
//   mapping: cellmetry-import/1
//   table: readings.csv                  # or {path, format: csv|jsonl, separator, decimal,
//                                        #     encoding: utf-8|latin1|windows-1252|cp1252}
//   units: {length: m, angle: deg}       # required: no silent default
//   robot: {name: ur3, joints: [q1, q2, q3, q4, q5, q6], angle: rad}
//   samples: {column: capture}           # rows sharing it are one robot state (default: a row)
//   poses: {column: pose}                # or {consecutive_joints: 1e-9} (default: a sample)
//   targets: {tool: {on: ur3}, world: {on: world}}
//   observations:
//     - camera: {column: camera}         # or a fixed name
//       target: tool                     # or {column: target}
//       position: [x, y, z]
//       rotation: {convention: euler, order: XYZ, axes: extrinsic, columns: [a, b, c]}
//       position_uncertainty: {columns: [ux, uy, uz], level: 0.95}   # or level: sigma;
//                                        # minimum: 0.0005 reads a rounded 0 as that
//       rotation_sigma: 0.01             # the instrument's stated orientation sigma
//   facts: {time: {column: t, unit: s}}
//
// Two or more tables instead of `table:` (a robot log and an instrument log), their rows joined
// into one (table_join.h):
//
//   tables: {robot: joints.csv, tracker: {path: leica.csv, encoding: latin1}}
//   join: {by: row}                      # or {by: time, columns: {robot: t, tracker: stamp},
//                                        #     tolerance_s: 0.01}
//
// and a column named where it is: `X` (the one table that has it), `tracker.X`, or
// {table: tracker, column: X}.
//
// Contract: ReadImportMapping checks every key (unknown keys with a "did you mean", missing
// required keys with what to add, conventions and units by name) and raises InputError at the
// mapping's line and column. Whether the named columns and tables exist is checked against the
// tables (JoinedTable, table_join.h), at the mapping's line, with the nearest column name.
// Every scale factor here turns the table's unit into cellmetry's (mm, rad, s, degC, kg).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/error.h"
#include "cellmetry/import/data_table.h"
#include "cellmetry/import/rotation_conventions.h"

namespace cellmetry {

inline constexpr char kImportMappingFormat[] = "cellmetry-import/1";

// A column the mapping names, and where it names it (for "no such column" errors).
struct ColumnRef {
  std::string name;
  SourceLocation where;
  std::string table;  // the table it is in when the mapping says ({table: T, column: C});
                      // empty: whichever table has it (table_join.h)
};

// A camera or target name: the same for every row, or read from a column.
struct NameSource {
  std::string fixed;
  std::optional<ColumnRef> column;
};

struct RotationSpec {
  RotationConvention convention;
  std::vector<ColumnRef> columns;  // convention.value_count() of them, in the convention's order
  SourceLocation where;
};

// The per-row uncertainty of an observed position: one column per axis (x, y, z of the camera),
// each an expanded uncertainty U = k * sigma at a stated coverage (or sigma itself, k = 1), in
// the entry's length unit. An instrument that rounds its uncertainties writes 0 for one below
// its last digit: `minimum` (> 0 when stated) is read for every cell below it.
struct PositionUncertaintySpec {
  std::vector<ColumnRef> columns;
  double coverage_factor = 1.0;  // k: sigma = U / k
  double minimum = 0.0;          // in the cells' unit and level; 0: none, a 0 cell is refused
  SourceLocation where;
};

// One (camera, target) pose in each row (rows leaving all its cells empty did not see it).
struct ObservationSpec {
  NameSource camera;
  NameSource target;
  bool camera_in_target = false;         // the table holds T_target_camera (inverted on import)
  std::vector<ColumnRef> position;       // x, y, z; empty when `transform` gives it
  std::optional<RotationSpec> rotation;  // none: position only (a dot)
  std::vector<ColumnRef> transform;      // 4x4 (16) or its top three rows (12), row-major
  bool transform_bottom_optional =
      false;  // from a prefix: T41..T44 read only when the table has them
  double transform_tolerance = 1e-3;
  double to_mm = 1.0;   // the table's length unit -> mm
  double to_rad = 1.0;  // the table's angle unit -> rad
  std::optional<PositionUncertaintySpec> position_uncertainty;
  std::optional<std::array<double, 3>> rotation_sigma_rad;  // about the camera's x, y, z
  SourceLocation where;
};

// A fact column: value_in_cellmetry_unit = value * scale + offset; or, for a time written as
// a date and time (date_time_format not empty, date_time.h), its seconds since the column's
// earliest.
struct FactSpec {
  ColumnRef column;
  double scale = 1.0;
  double offset = 0.0;
  std::string date_time_format;
};

// One table the mapping reads.
struct TableSpec {
  std::string name;  // its key under tables:, which column references use; "" for `table:`
  std::string path;  // resolved against the mapping's folder
  bool json_lines = false;
  CsvDialect csv;
  SourceLocation where;
};

// How the rows of several tables become one: row i of each (kRow), or each row of the first
// table with the row of every other nearest in time, within a tolerance (kTime).
enum class JoinKind { kRow, kTime };

struct JoinSpec {
  JoinKind by = JoinKind::kRow;
  std::vector<FactSpec> time_s;  // kTime: each table's time column, in the order of `tables`
  double tolerance_s = 0.0;
  SourceLocation where;
};

enum class PoseGrouping { kEachSample, kColumn, kConsecutiveJoints };

struct ImportMapping {
  std::string file;  // the mapping's path
  std::string description;
  std::vector<TableSpec> tables;  // one (table:) or more (tables:), in the mapping's order
  JoinSpec join;                  // for more than one table

  std::string robot;
  std::vector<ColumnRef> joints;
  double joint_to_rad = 1.0;

  std::optional<ColumnRef> sample_column;
  PoseGrouping poses = PoseGrouping::kEachSample;
  std::optional<ColumnRef> pose_column;
  double pose_joint_tolerance_rad = 0.0;

  std::vector<std::pair<std::string, std::string>> targets;  // name -> robot or "world"
  std::vector<ObservationSpec> observations;

  std::optional<FactSpec> time_s;
  std::optional<FactSpec> temperature_c;
  std::optional<FactSpec> payload_kg;

  // Every column the mapping names, for checking them against the table.
  std::vector<const ColumnRef*> AllColumns() const;
};

ImportMapping ReadImportMapping(const std::string& path);

}  // namespace cellmetry
