// Reading TARGETS.csv (compensation_targets.h).
#include "cellmetry/compensation/compensation_targets.h"

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/csv_table.h"

namespace cellmetry {
namespace {

const std::vector<std::string> kPosition = {"x_mm", "y_mm", "z_mm"};
const std::vector<std::string> kRotation = {"rx_rad", "ry_rad", "rz_rad"};

std::vector<std::string> Numbered(const std::string& prefix, const std::string& suffix, int n) {
  std::vector<std::string> names;
  for (int j = 1; j <= n; ++j) names.push_back(prefix + std::to_string(j) + suffix);
  return names;
}

// Which of `group`'s columns the header has: all (true), none (false); some is an error.
bool HasGroup(const CsvTable& table, const std::vector<std::string>& group,
              const std::string& what) {
  int present = 0;
  for (const auto& c : group) present += table.HasColumn(c);
  if (present == 0) return false;
  if (present == static_cast<int>(group.size())) return true;
  for (const auto& c : group) {
    if (!table.HasColumn(c)) {
      throw InputError({table.path(), 1, 0}, "missing column '" + c + "' (" + what + ")",
                       "Give all of " + group.front() + " ... " + group.back() + ", or none");
    }
  }
  return true;
}

// A row's cells of `group`: all filled (true), all empty (false); some is an error.
bool RowHasGroup(const CsvTable& table, size_t row, const std::vector<std::string>& group) {
  int filled = 0;
  for (const auto& c : group) filled += table.HasValue(row, c);
  if (filled == 0) return false;
  if (filled == static_cast<int>(group.size())) return true;
  for (const auto& c : group) {
    if (!table.HasValue(row, c)) {
      throw table.Error(row, c, "empty cell",
                        "Fill in every one of " + group.front() + " ... " + group.back() +
                            " on this row, or none");
    }
  }
  return true;
}

Eigen::Vector3d Vector3Of(const CsvTable& table, size_t row,
                          const std::vector<std::string>& columns) {
  return {table.Number(row, columns[0]), table.Number(row, columns[1]),
          table.Number(row, columns[2])};
}

std::vector<int> ApproachOf(const CsvTable& table, size_t row,
                            const std::vector<std::string>& columns) {
  std::vector<int> approach;
  for (const auto& c : columns) {
    const double value = table.Number(row, c);
    if (value != -1.0 && value != 0.0 && value != 1.0) {
      throw table.Error(row, c, "an approach direction must be -1, 0 or 1",
                        "Write 1 (the joint moves up into the target), -1 (down) or 0");
    }
    approach.push_back(static_cast<int>(value));
  }
  return approach;
}

void ReadContext(const CsvTable& table, size_t row, CompensationTarget* target) {
  if (table.HasValue(row, "payload_kg")) {
    target->payload_kg = table.Number(row, "payload_kg");
    if (target->payload_kg < 0.0) {
      throw table.Error(row, "payload_kg", "a payload cannot be negative",
                        "Give the load at the flange in kg");
    }
  }
  if (table.HasValue(row, "temperature_c")) {
    target->temperature_c = table.Number(row, "temperature_c");
  }
  if (table.HasValue(row, "t_s")) target->time_s = table.Number(row, "t_s");
}

// Which column groups the file has (compensation_targets.h).
struct Columns {
  bool position, rotation, joints, approach;
  std::vector<std::string> q, approach_j;
};

CompensationTarget ReadRow(const CsvTable& table, size_t row, const Columns& columns) {
  CompensationTarget t;
  t.line = table.line_of(row);
  t.id = table.HasValue(row, "id") ? table.Text(row, "id") : "line " + std::to_string(t.line);
  // A row with x y z empty is a joint target, in a file of poses too.
  const bool position = columns.position && (!columns.joints || RowHasGroup(table, row, kPosition));
  const bool rotation = columns.rotation && RowHasGroup(table, row, kRotation);
  if (rotation && !position) {
    throw table.Error(row, kRotation.front(), "a rotation without a position",
                      "Give x_mm, y_mm, z_mm on this row, or leave the rotation empty");
  }
  t.kind = !position  ? CompensationTarget::Kind::kJoints
           : rotation ? CompensationTarget::Kind::kPose
                      : CompensationTarget::Kind::kPosition;
  if (position) t.p_world_tool_mm = Vector3Of(table, row, kPosition);
  if (rotation) {
    const Eigen::Vector3d r = Vector3Of(table, row, kRotation);
    t.R_world_tool = RotationFromRvec(r.data());
  }
  if (columns.joints && (!position || RowHasGroup(table, row, columns.q))) {
    for (const auto& c : columns.q) t.q_rad.push_back(table.Number(row, c));
  }
  if (columns.approach && RowHasGroup(table, row, columns.approach_j)) {
    t.approach = ApproachOf(table, row, columns.approach_j);
  }
  ReadContext(table, row, &t);
  return t;
}

}  // namespace

std::vector<CompensationTarget> ReadCompensationTargets(const std::string& path, int num_joints) {
  const CsvTable table = CsvTable::Read(path);
  const auto q_columns = Numbered("q", "_rad", num_joints);
  const auto approach_columns = Numbered("approach_j", "", num_joints);
  std::vector<std::string> known = {"id", "payload_kg", "temperature_c", "t_s"};
  for (const auto* group : {&kPosition, &kRotation, &q_columns, &approach_columns}) {
    known.insert(known.end(), group->begin(), group->end());
  }
  table.RejectUnknownColumns(known);
  const bool position = HasGroup(table, kPosition, "the tool's position");
  const bool rotation = HasGroup(table, kRotation, "the tool's rotation");
  const bool joints = HasGroup(table, q_columns, "joint values");
  const bool approach = HasGroup(table, approach_columns, "approach directions");
  if (rotation && !position) {
    throw InputError({path, 1, 0}, "rotation columns without x_mm, y_mm, z_mm",
                     "Give the tool's position with its rotation");
  }
  if (rotation && num_joints < 6) {
    throw InputError(
        {path, 1, 0},
        "the robot has " + std::to_string(num_joints) + " joints: it cannot turn its tool at will",
        "Give positions only (x_mm, y_mm, z_mm)");
  }
  if (!position && !joints) {
    throw InputError({path, 1, 0}, "no target columns",
                     "Give x_mm, y_mm, z_mm (and rx_rad, ry_rad, rz_rad) or q1_rad ... q" +
                         std::to_string(num_joints) + "_rad");
  }
  const Columns columns{position, rotation, joints, approach, q_columns, approach_columns};
  std::vector<CompensationTarget> targets;
  for (size_t row = 0; row < table.num_rows(); ++row) {
    targets.push_back(ReadRow(table, row, columns));
  }
  if (targets.empty()) {
    throw InputError({path, 1, 0}, "no targets", "Add one row per target below the header");
  }
  return targets;
}

}  // namespace cellmetry
