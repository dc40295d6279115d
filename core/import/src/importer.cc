// The importer (importer.h): a table's rows under a mapping become samples and observations of a
// recording, every cell converted to mm and rad and checked where it stands.
#include "cellmetry/import/importer.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/config_node.h"

namespace cellmetry {
namespace {

// What no camera in a robot cell measures and no joint reads (as the recording reader says).
constexpr double kMaxPositionMm = 1e5;  // 100 m
constexpr double kMaxJointRad = 100.0;  // sixteen turns
// No rotation needs an angle beyond a full turn: one is degrees read as radians.
constexpr double kFullTurn = 2 * M_PI + 1e-6;
// Rows of one sample are one robot state: their joints and facts agree to rounding.
constexpr double kSameSampleTolerance = 1e-9;

std::string Text(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.10g", value);
  return text;
}

using Column = JoinedTable::Column;

std::vector<Column> Bind(const std::vector<ColumnRef>& refs, const JoinedTable& table) {
  std::vector<Column> columns;
  for (const auto& ref : refs) columns.push_back(table.Bind(ref));
  return columns;
}

// An observation entry with its columns found in the table.
struct BoundObservation {
  const ObservationSpec* spec = nullptr;
  std::optional<Column> camera, target;
  std::vector<Column> position, rotation, transform, uncertainty;
  std::vector<Column> cells;  // every numeric cell of the entry, in reading order
};

BoundObservation BindObservation(const ObservationSpec& spec, const JoinedTable& table) {
  BoundObservation b;
  b.spec = &spec;
  if (spec.camera.column) b.camera = table.Bind(*spec.camera.column);
  if (spec.target.column) b.target = table.Bind(*spec.target.column);
  b.position = Bind(spec.position, table);
  if (spec.rotation) b.rotation = Bind(spec.rotation->columns, table);
  if (!spec.transform.empty()) {
    std::vector<ColumnRef> refs = spec.transform;
    // A prefix names the bottom row too; tables usually leave 0 0 0 1 out.
    if (spec.transform_bottom_optional) {
      bool any_bottom = false;
      for (size_t i = 12; i < 16; ++i) any_bottom |= table.Find(refs[i]).has_value();
      if (!any_bottom) refs.resize(12);
    }
    b.transform = Bind(refs, table);
  }
  if (spec.camera_in_target && !spec.rotation && spec.transform.empty()) {
    throw InputError(spec.where,
                     "pose_of: camera_in_target needs the rotation to turn the "
                     "camera's pose into the target's",
                     "Give rotation: too, or drop pose_of: for a target's position in the camera");
  }
  if (spec.position_uncertainty) b.uncertainty = Bind(spec.position_uncertainty->columns, table);
  for (const auto* list : {&b.position, &b.rotation, &b.transform, &b.uncertainty}) {
    b.cells.insert(b.cells.end(), list->begin(), list->end());
  }
  return b;
}

// A camera or target name from its cell: not empty, nothing that breaks a CSV line.
std::string NameCell(const JoinedTable& table, size_t row, Column column, const std::string& what) {
  const std::string& name = table.Cell(row, column);
  if (name.empty()) throw table.Error(row, column, "empty cell", "Name the " + what + " here");
  if (name.find_first_of(",\"\n") != std::string::npos) {
    throw table.Error(row, column, "'" + name + "' holds ',' '\"' or a line break",
                      "Name the " + what + " with a plain word (cam1, tool)");
  }
  return name;
}

// The first and the other rows of one sample.
struct SampleRows {
  size_t first_row = 0;
  std::string pose_key;
};

bool Agree(double a, double b) {
  return std::abs(a - b) <= kSameSampleTolerance * std::max(1.0, std::abs(a));
}

class Importer {
 public:
  Importer(const ImportMapping& mapping, const JoinedTable& table) : m_(mapping), table_(table) {
    joints_ = Bind(m_.joints, table_);
    if (m_.sample_column) sample_column_ = table_.Bind(*m_.sample_column);
    if (m_.pose_column) pose_column_ = table_.Bind(*m_.pose_column);
    for (const auto& spec : m_.observations) bound_.push_back(BindObservation(spec, table_));
    const std::pair<const std::optional<FactSpec>*, std::optional<Column>*> facts[] = {
        {&m_.time_s, &time_}, {&m_.temperature_c, &temperature_}, {&m_.payload_kg, &payload_}};
    for (const auto& [spec, column] : facts) {
      if (*spec) *column = table_.Bind((*spec)->column);
    }
    for (const auto& [name, carrier] : m_.targets) targets_[name] = carrier;
    if (time_ && !m_.time_s->date_time_format.empty()) time_origin_ = EarliestDateTime();
  }

  Recording Run() {
    Recording r;
    r.description = m_.description.empty() ? "" : m_.description + " ";
    r.description += "(imported from " + table_.FileNames() + " by " +
                     std::filesystem::path(m_.file).filename().string() + ")";
    r.robots[m_.robot] = static_cast<int>(m_.joints.size());
    r.targets = targets_;
    for (const auto& b : bound_) {
      if (!b.spec->camera.column) AddCamera(b.spec->camera.fixed, &r);
    }
    for (size_t row = 0; row < table_.num_rows(); ++row) {
      const int sample = SampleOf(row, &r);
      for (const auto& b : bound_) ReadObservation(b, row, sample, &r);
    }
    if (r.observations.empty()) {
      throw InputError(
          m_.tables.front().where,
          "no observation in " + table_.FileNames() + ": every observation cell is empty",
          "Point observations: at the columns that hold the measured poses");
    }
    NumberPoses(&r);
    return r;
  }

 private:
  void AddCamera(const std::string& name, Recording* r) {
    if (!r->HasCamera(name)) r->cameras.push_back(name);
  }

  double Limited(size_t row, Column column, double scale, double max_abs,
                 const std::string& unit_hint) const {
    const double value = table_.Number(row, column) * scale;
    if (std::abs(value) > max_abs) {
      throw table_.Error(row, column,
                         "'" + table_.Cell(row, column) + "' is beyond any measurement of it",
                         unit_hint);
    }
    return value;
  }

  // The sample this row belongs to (a new one, or the one its sample column names).
  int SampleOf(size_t row, Recording* r) {
    const std::string key =
        sample_column_ ? table_.Cell(row, *sample_column_) : std::to_string(row);
    if (sample_column_ && key.empty()) {
      throw table_.Error(row, *sample_column_, "empty cell",
                         "Every row needs the sample it belongs to");
    }
    const std::string pose_key = pose_column_ ? table_.Cell(row, *pose_column_) : "";
    if (pose_column_ && pose_key.empty()) {
      throw table_.Error(row, *pose_column_, "empty cell",
                         "Every row needs the commanded pose it repeats");
    }
    Sample sample = RobotState(row);
    sample.id = static_cast<int>(r->samples.size());
    const auto found = sample_of_key_.find(key);
    if (found == sample_of_key_.end()) {
      sample_of_key_[key] = sample.id;
      rows_.push_back({row, pose_key});
      r->samples.push_back(std::move(sample));
      return r->samples.back().id;
    }
    CheckSameState(row, key, r->samples[found->second], rows_[found->second], sample, pose_key);
    return found->second;
  }

  // The robot's state in a row: its joints, and the time, temperature and payload where mapped.
  Sample RobotState(size_t row) const {
    Sample sample;
    sample.robot = m_.robot;
    for (size_t j = 0; j < joints_.size(); ++j) {
      sample.q.push_back(Limited(row, joints_[j], m_.joint_to_rad, kMaxJointRad,
                                 m_.joint_to_rad == 1.0
                                     ? "The mapping reads the joints in rad; if they are degrees, "
                                       "say robot: {angle: deg}"
                                     : "Check the value (the joints are read in degrees)"));
    }
    if (time_) sample.time_s = Fact(row, *time_, *m_.time_s);
    if (temperature_) sample.temperature_c = Fact(row, *temperature_, *m_.temperature_c);
    if (payload_) sample.payload_kg = Fact(row, *payload_, *m_.payload_kg);
    return sample;
  }

  // Another row of a sample already seen must be the same robot state: joints, facts and pose.
  void CheckSameState(size_t row, const std::string& key, const Sample& first,
                      const SampleRows& first_rows, const Sample& sample,
                      const std::string& pose_key) const {
    const std::string where =
        "sample '" + key + "' (data row " + std::to_string(first_rows.first_row + 1) + ")";
    const std::string hint =
        "The rows of one sample are one robot state and must agree; check "
        "samples: {column: ...} in the mapping";
    for (size_t j = 0; j < joints_.size(); ++j) {
      if (!Agree(first.q[j], sample.q[j])) {
        throw table_.Error(row, joints_[j],
                           where + " has " + Text(first.q[j]) + " rad there but " +
                               Text(sample.q[j]) + " rad here",
                           hint);
      }
    }
    const std::pair<const std::optional<double>*, const std::optional<double>*> pairs[] = {
        {&first.time_s, &sample.time_s},
        {&first.temperature_c, &sample.temperature_c},
        {&first.payload_kg, &sample.payload_kg}};
    const std::optional<Column> columns[] = {time_, temperature_, payload_};
    for (int f = 0; f < 3; ++f) {
      const auto& [a, b] = pairs[f];
      if (*a && *b && !Agree(**a, **b)) {
        throw table_.Error(row, *columns[f],
                           where + " has " + Text(**a) + " there but " + Text(**b) + " here", hint);
      }
    }
    if (pose_column_ && pose_key != first_rows.pose_key) {
      throw table_.Error(
          row, *pose_column_,
          where + " is pose '" + first_rows.pose_key + "' there but '" + pose_key + "' here", hint);
    }
  }

  std::optional<double> Fact(size_t row, Column column, const FactSpec& spec) const {
    if (table_.IsEmpty(row, column)) return std::nullopt;
    if (!spec.date_time_format.empty()) {
      return table_.DateTime(row, column, spec.date_time_format).SecondsSince(time_origin_);
    }
    return table_.Number(row, column) * spec.scale + spec.offset;
  }

  // A clock's time of day is no time for a warm-up: date-times count from the column's earliest.
  ClockTime EarliestDateTime() const {
    std::optional<ClockTime> earliest;
    for (size_t row = 0; row < table_.num_rows(); ++row) {
      if (table_.IsEmpty(row, *time_)) continue;
      const ClockTime t = table_.DateTime(row, *time_, m_.time_s->date_time_format);
      if (!earliest || t < *earliest) earliest = t;
    }
    return earliest.value_or(ClockTime{});
  }

  void ReadObservation(const BoundObservation& b, size_t row, int sample, Recording* r) {
    const ObservationSpec& spec = *b.spec;
    size_t filled = 0;
    std::optional<Column> first_empty;
    for (const Column& c : b.cells) {
      if (!table_.IsEmpty(row, c)) {
        ++filled;
      } else if (!first_empty) {
        first_empty = c;
      }
    }
    if (filled == 0) return;  // not seen in this row
    Observation o;
    o.sample = sample;
    o.camera = spec.camera.column ? NameCell(table_, row, *b.camera, "camera") : spec.camera.fixed;
    o.target = spec.target.column ? NameCell(table_, row, *b.target, "target") : spec.target.fixed;
    if (first_empty) {
      throw table_.Error(
          row, *first_empty,
          "the observation of '" + o.target + "' in '" + o.camera + "' is partly filled in",
          "Fill in every cell of it, or leave all of them empty where the target "
          "was not seen");
    }
    CheckTargetListed(b, row, o.target);
    const std::string length_hint =
        spec.to_mm == 1.0 ? "Check the value (the mapping reads lengths in mm)"
                          : "The mapping reads lengths in m; if the table holds millimetres, say "
                            "units: {length: mm}";
    TablePose pose = b.transform.empty() ? ReadPositionAndRotation(b, row, length_hint)
                                         : ReadTransform(b, row, length_hint);
    if (spec.camera_in_target) pose.T = pose.T.inverse();
    o.position_mm = pose.T.t;
    if (pose.has_rotation) o.rvec = RvecFromRotation(pose.T.R);
    if (pose.rotation_vector && !spec.camera_in_target) o.rvec = *pose.rotation_vector;
    if (spec.position_uncertainty) o.covariance_mm2 = PositionCovariance(b, row, length_hint);
    if (spec.rotation_sigma_rad) {
      const auto& sigma = *spec.rotation_sigma_rad;
      o.rotation_covariance_rad2 =
          Eigen::Vector3d(sigma[0] * sigma[0], sigma[1] * sigma[1], sigma[2] * sigma[2])
              .asDiagonal();
    }
    AddCamera(o.camera, r);
    r->observations.push_back(std::move(o));
  }

  void CheckTargetListed(const BoundObservation& b, size_t row, const std::string& target) const {
    if (targets_.count(target)) return;
    std::vector<std::string> names;
    for (const auto& [name, carrier] : targets_) names.push_back(name);
    const std::string nearest = NearestWord(target, names);
    throw table_.Error(row, *b.target, "unknown target '" + target + "'",
                       nearest.empty() ? "List it under targets: in the mapping"
                                       : "Did you mean '" + nearest +
                                             "'? Or list it under targets: in the mapping");
  }

  // An observation's pose as the table gives it (mm), before pose_of: camera_in_target turns it.
  struct TablePose {
    Pose T;
    bool has_rotation = false;
    // The table's own numbers where it gives a rotation vector, kept as written rather than
    // taken back from the matrix (which would move them by rounding, or by a full turn).
    std::optional<Eigen::Vector3d> rotation_vector;
  };

  // A 4x4 (or 3x4) transform, row by row: its bottom row must be 0 0 0 1, its rotation a
  // rotation within the mapping's tolerance.
  TablePose ReadTransform(const BoundObservation& b, size_t row,
                          const std::string& length_hint) const {
    const ObservationSpec& spec = *b.spec;
    TablePose pose;
    double v[16];
    for (size_t i = 0; i < b.transform.size(); ++i) v[i] = table_.Number(row, b.transform[i]);
    for (int i = 0; i < 3; ++i) {
      pose.T.t[i] = Limited(row, b.transform[4 * i + 3], spec.to_mm, kMaxPositionMm, length_hint);
    }
    if (b.transform.size() == 16) {
      const double bottom[4] = {0, 0, 0, 1};
      for (int k = 0; k < 4; ++k) {
        if (std::abs(v[12 + k] - bottom[k]) > spec.transform_tolerance) {
          throw table_.Error(row, b.transform[12 + k],
                             "a transform's bottom row is 0 0 0 1, this cell holds " +
                                 table_.Cell(row, b.transform[12 + k]),
                             "Check that the 16 columns are the matrix row by row");
        }
      }
    }
    RotationConvention matrix;
    matrix.kind = RotationKind::kMatrix;
    matrix.tolerance = spec.transform_tolerance;
    const double R[9] = {v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10]};
    pose.T.R = Rotation(row, b.transform[0], matrix, R);
    pose.has_rotation = true;
    return pose;
  }

  // Three position cells and, where the mapping gives one, the rotation in its convention;
  // angles beyond a full turn are refused as a unit mistaken.
  TablePose ReadPositionAndRotation(const BoundObservation& b, size_t row,
                                    const std::string& length_hint) const {
    const ObservationSpec& spec = *b.spec;
    TablePose pose;
    for (int i = 0; i < 3; ++i) {
      pose.T.t[i] = Limited(row, b.position[i], spec.to_mm, kMaxPositionMm, length_hint);
    }
    if (!spec.rotation) return pose;
    const RotationConvention& c = spec.rotation->convention;
    double v[9];
    for (size_t i = 0; i < b.rotation.size(); ++i) {
      v[i] = table_.Number(row, b.rotation[i]) * (c.values_are_angles() ? spec.to_rad : 1.0);
      if (c.values_are_angles() && std::abs(v[i]) > kFullTurn) {
        throw table_.Error(
            row, b.rotation[i],
            "'" + table_.Cell(row, b.rotation[i]) + (spec.to_rad == 1.0 ? " rad" : " deg") +
                "' is more than a full turn",
            spec.to_rad == 1.0 ? "The mapping reads these angles in rad; if they are degrees, "
                                 "say units: {angle: deg} (or angle: deg in this observation)"
                               : "Check the value");
      }
    }
    pose.T.R = Rotation(row, b.rotation[0], c, v);
    pose.has_rotation = true;
    if (c.kind == RotationKind::kRotationVector)
      pose.rotation_vector = Eigen::Vector3d(v[0], v[1], v[2]);
    return pose;
  }

  // The position's covariance from the row's uncertainty cells, in mm^2: diagonal, each axis'
  // standard uncertainty u = U / k squared (U at least the stated minimum). An expanded
  // uncertainty U at a level of confidence is k standard uncertainties, k the coverage factor
  // of a normal distribution (1.96 at 95 %; GUM, JCGM 100:2008, 6.2.1 and G.1.3, Table G.1);
  // PositionUncertaintySpec carries k.
  Eigen::Matrix3d PositionCovariance(const BoundObservation& b, size_t row,
                                     const std::string& length_hint) const {
    const ObservationSpec& spec = *b.spec;
    Eigen::Vector3d variance_mm2;
    const PositionUncertaintySpec& uncertainty = *spec.position_uncertainty;
    for (int i = 0; i < 3; ++i) {
      const Column cell = b.uncertainty[i];
      const double stated_mm = Limited(row, cell, spec.to_mm, kMaxPositionMm, length_hint);
      if (stated_mm < 0.0 || (stated_mm == 0.0 && uncertainty.minimum == 0.0)) {
        throw table_.Error(
            row, cell, "an uncertainty of " + table_.Cell(row, cell) + " is not positive",
            stated_mm < 0.0
                ? "Check the cell: an uncertainty is a size"
                : "A zero says 'known perfectly' and would weigh the observation without bound; "
                  "if the instrument rounds its uncertainties, state the least one a cell stands "
                  "for: position_uncertainty: {..., minimum: 0.0005}");
      }
      const double u_mm =
          std::max(stated_mm, uncertainty.minimum * spec.to_mm) / uncertainty.coverage_factor;
      variance_mm2[i] = u_mm * u_mm;
    }
    return variance_mm2.asDiagonal();
  }

  Eigen::Matrix3d Rotation(size_t row, Column column, const RotationConvention& c,
                           const double* values) const {
    std::string problem;
    const Eigen::Matrix3d R = ToRotation(c, values, &problem);
    if (problem.empty()) return R;
    const std::string hint =
        c.kind == RotationKind::kQuaternion
            ? "Check the four cells and their order (" + c.Describe() +
                  "); if they are rounded, raise tolerance: in the mapping's rotation"
            : "Check the nine cells (row by row: r11 r12 r13 r21 ...); if they are rounded, "
              "raise tolerance: in the mapping";
    throw table_.Error(row, column, problem, hint);
  }

  void NumberPoses(Recording* r) const {
    std::map<std::string, int> pose_of_key;
    for (size_t s = 0; s < r->samples.size(); ++s) {
      Sample& sample = r->samples[s];
      switch (m_.poses) {
        case PoseGrouping::kEachSample: sample.pose = sample.id; break;
        case PoseGrouping::kColumn: {
          const auto [it, fresh] =
              pose_of_key.emplace(rows_[s].pose_key, static_cast<int>(pose_of_key.size()));
          sample.pose = it->second;
          break;
        }
        case PoseGrouping::kConsecutiveJoints: {
          bool same = s > 0;
          for (size_t j = 0; same && j < sample.q.size(); ++j) {
            same = std::abs(sample.q[j] - r->samples[s - 1].q[j]) <= m_.pose_joint_tolerance_rad;
          }
          sample.pose = s == 0 ? 0 : r->samples[s - 1].pose + (same ? 0 : 1);
          break;
        }
      }
    }
  }

  const ImportMapping& m_;
  const JoinedTable& table_;
  std::vector<Column> joints_;
  std::optional<Column> sample_column_, pose_column_, time_, temperature_, payload_;
  ClockTime time_origin_;  // a date-time column's earliest, which its times count from
  std::vector<BoundObservation> bound_;
  std::map<std::string, std::string> targets_;
  std::map<std::string, int> sample_of_key_;
  std::vector<SampleRows> rows_;  // per sample
};

}  // namespace

JoinedTable ReadMappedTables(const ImportMapping& mapping) {
  std::vector<DataTable> tables;
  for (const TableSpec& spec : mapping.tables) {
    // What is there but not a regular file (a FIFO, a device) the reader refuses by name.
    std::error_code ec;
    if (!std::filesystem::exists(spec.path, ec)) {
      throw InputError(spec.where, "no table at '" + spec.path + "'",
                       "Give the table's path relative to the mapping file");
    }
    tables.push_back(spec.json_lines ? ReadJsonLinesTable(spec.path)
                                     : ReadCsvTable(spec.path, spec.csv));
  }
  return JoinedTable::Join(mapping, std::move(tables));
}

Recording ImportTable(const ImportMapping& mapping, const JoinedTable& table) {
  return Importer(mapping, table).Run();
}

Recording ImportRecording(const std::string& mapping_path) {
  const ImportMapping mapping = ReadImportMapping(mapping_path);
  return ImportTable(mapping, ReadMappedTables(mapping));
}

}  // namespace cellmetry
