// ReadImportMapping (import_mapping.h): the mapping file read key by key, every mistake an
// InputError at its line and column with what to write instead.
#include "cellmetry/import/import_mapping.h"

#include <cmath>
#include <tuple>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/import/date_time.h"
#include "mapping_keys.h"

namespace cellmetry {
namespace {

using import_keys::AngleToRad;
using import_keys::Column;
using import_keys::ColumnOfMap;
using import_keys::Columns;
using import_keys::LengthToMm;
using import_keys::OneOf;
using import_keys::ReadFact;
using import_keys::ReadUncertainties;
using import_keys::Required;

// PREFIX11 .. PREFIX<rows><cols>, row-major, each placed at the prefix's key.
std::vector<ColumnRef> PrefixedColumns(const ConfigNode& prefix, int rows, int cols) {
  std::vector<ColumnRef> columns;
  const std::string p = prefix.AsString();
  for (int r = 1; r <= rows; ++r) {
    for (int c = 1; c <= cols; ++c) {
      columns.push_back({p + std::to_string(r) + std::to_string(c), prefix.location(), ""});
    }
  }
  return columns;
}

NameSource ReadName(const ConfigNode& node, const std::string& what) {
  NameSource source;
  if (node.IsMap()) {
    node.ExpectKeys({"table", "column"});
    source.column = ColumnOfMap(
        node, "Write {column: NAME}: the column that names the " + what + " in each row");
  } else {
    source.fixed = node.AsString();
    if (source.fixed.find_first_of(",\"\n") != std::string::npos || source.fixed.empty()) {
      throw node.Error("a " + what + " name may not be empty or hold ',' '\"' or a line break",
                       "Choose a plain name (cam1, tool)");
    }
  }
  return source;
}

std::vector<std::string> MatrixNames(int rows, int cols) {
  std::vector<std::string> names;
  for (int r = 1; r <= rows; ++r) {
    for (int c = 1; c <= cols; ++c) names.push_back("r" + std::to_string(r) + std::to_string(c));
  }
  return names;
}

double Tolerance(const ConfigNode& node) {
  return node.GetDoubleIn("tolerance", 1e-3, 1e-15, 0.5,
                          "How far from a rotation the numbers may be, e.g. 1e-6");
}

// `convention: euler`: the turn order, intrinsic or extrinsic, and an angle column per turn.
void ReadEulerRotation(const ConfigNode& node, RotationSpec* spec) {
  node.ExpectKeys({"convention", "order", "axes", "columns"});
  RotationConvention& c = spec->convention;
  c.kind = RotationKind::kEuler;
  const ConfigNode order = Required(node, "order", "Give the axes in turn order, e.g. order: ZYX");
  const auto axes = ParseEulerOrder(order.AsString());
  if (!axes) {
    throw order.Error("'" + order.AsString() + "' is not an Euler sequence",
                      "Write three capital axes, no axis twice in a row: XYZ, XZY, YXZ, YZX, "
                      "ZXY, ZYX, XYX, XZX, YXY, YZY, ZXZ, ZYZ (and say intrinsic or extrinsic "
                      "under axes:; scipy's lowercase 'xyz' is extrinsic)");
  }
  c.euler_axes = *axes;
  c.intrinsic = OneOf(Required(node, "axes",
                               "Say whether each turn is about the turned frame's axes "
                               "(axes: intrinsic) or the fixed frame's (axes: extrinsic)"),
                      {"intrinsic", "extrinsic"}, "Euler axes") == "intrinsic";
  const std::string o = order.AsString();
  spec->columns = Columns(Required(node, "columns", "List the three angles' columns"),
                          {std::string("angle about ") + o[0], std::string("angle about ") + o[1],
                           std::string("angle about ") + o[2]});
}

RotationSpec ReadRotation(const ConfigNode& node) {
  RotationSpec spec;
  spec.where = node.location();
  node.ExpectMap();
  const std::string convention =
      OneOf(Required(node, "convention",
                     "Say how the rotation is written: euler, rpy, quaternion, rotation_vector or "
                     "matrix"),
            {"euler", "rpy", "quaternion", "rotation_vector", "matrix"}, "rotation convention");
  RotationConvention& c = spec.convention;
  if (convention == "euler") {
    ReadEulerRotation(node, &spec);
  } else if (convention == "rpy") {
    node.ExpectKeys({"convention", "columns"});
    c.kind = RotationKind::kRollPitchYaw;
    spec.columns = Columns(Required(node, "columns", "List [roll, pitch, yaw] columns"),
                           {"roll", "pitch", "yaw"});
  } else if (convention == "quaternion") {
    node.ExpectKeys({"convention", "order", "columns", "tolerance"});
    c.kind = RotationKind::kQuaternion;
    c.scalar_first = OneOf(Required(node, "order",
                                    "Say where the scalar part is: order: wxyz (scalar first) or "
                                    "order: xyzw (scalar last, as ROS and scipy)"),
                           {"wxyz", "xyzw"}, "quaternion order") == "wxyz";
    c.tolerance = Tolerance(node);
    spec.columns = Columns(Required(node, "columns", "List the quaternion's four columns"),
                           c.scalar_first ? std::vector<std::string>{"w", "x", "y", "z"}
                                          : std::vector<std::string>{"x", "y", "z", "w"});
  } else if (convention == "rotation_vector") {
    node.ExpectKeys({"convention", "columns"});
    c.kind = RotationKind::kRotationVector;
    spec.columns =
        Columns(Required(node, "columns", "List [rx, ry, rz] columns"), {"rx", "ry", "rz"});
  } else {
    node.ExpectKeys({"convention", "columns", "prefix", "tolerance"});
    c.kind = RotationKind::kMatrix;
    c.tolerance = Tolerance(node);
    if (node.Has("prefix") == node.Has("columns")) {
      throw node.Error("give the matrix's columns or their prefix, one of them",
                       "prefix: R reads R11, R12, ... R33; columns: lists nine names row by row");
    }
    spec.columns = node.Has("prefix") ? PrefixedColumns(node["prefix"], 3, 3)
                                      : Columns(node["columns"], MatrixNames(3, 3));
  }
  return spec;
}

// A fixed target name must be one the mapping's targets: lists.
void CheckTargetListed(const ConfigNode& target, const std::string& name,
                       const ImportMapping& mapping) {
  std::vector<std::string> names;
  for (const auto& [listed, carrier] : mapping.targets) {
    if (listed == name) return;
    names.push_back(listed);
  }
  const std::string nearest = NearestWord(name, names);
  throw target.Error("target '" + name + "' is not under targets:",
                     nearest.empty() ? "List it under targets: with what carries it"
                                     : "Did you mean '" + nearest + "'?");
}

// `transform:` a 4x4 (or its top 3x4) by prefix or by its columns, row by row.
void ReadTransformColumns(const ConfigNode& t, ObservationSpec* spec) {
  t.ExpectMap();
  t.ExpectKeys({"prefix", "columns", "tolerance"});
  spec->transform_tolerance = Tolerance(t);
  if (t.Has("prefix") == t.Has("columns")) {
    throw t.Error("give the transform's columns or their prefix, one of them",
                  "prefix: T reads T11 .. T34 (and T41 .. T44 when the table has them); "
                  "columns: lists 16 (or the top 12) names row by row");
  }
  if (t.Has("prefix")) {
    spec->transform = PrefixedColumns(t["prefix"], 4, 4);
    spec->transform_bottom_optional = true;
  } else {
    const ConfigNode list = t["columns"];
    const size_t n = list.IsSequence() ? list.Elements().size() : 0;
    spec->transform = Columns(list, MatrixNames(n == 12 ? 3 : 4, 4));
  }
}

ObservationSpec ReadObservation(const ConfigNode& node, const ImportMapping& mapping, double to_mm,
                                double to_rad) {
  node.ExpectKeys({"camera", "target", "pose_of", "position", "rotation", "transform", "length",
                   "angle", "position_uncertainty", "rotation_sigma"});
  ObservationSpec spec;
  spec.where = node.location();
  spec.camera = ReadName(Required(node, "camera",
                                  "Name the camera (camera: cam1) or the column "
                                  "naming it (camera: {column: camera})"),
                         "camera");
  const ConfigNode target = Required(node, "target",
                                     "Name the target (target: tool) or the "
                                     "column naming it (target: {column: target})");
  spec.target = ReadName(target, "target");
  if (!spec.target.fixed.empty()) CheckTargetListed(target, spec.target.fixed, mapping);
  if (node.Has("pose_of")) {
    spec.camera_in_target = OneOf(node["pose_of"], {"target_in_camera", "camera_in_target"},
                                  "pose direction") == "camera_in_target";
  }
  spec.to_mm = node.Has("length") ? LengthToMm(node["length"]) : to_mm;
  spec.to_rad = node.Has("angle") ? AngleToRad(node["angle"]) : to_rad;
  if (node.Has("transform")) {
    const ConfigNode t = node["transform"];
    if (node.Has("position") || node.Has("rotation")) {
      throw t.Error("a transform gives both position and rotation",
                    "Give transform: alone, or position: and rotation: without it");
    }
    ReadTransformColumns(t, &spec);
    ReadUncertainties(node, &spec);
    return spec;
  }
  spec.position = Columns(Required(node, "position",
                                   "List the target's position columns: position: [x, y, z] (or "
                                   "give transform: for a 4x4 matrix)"),
                          {"x", "y", "z"});
  if (node.Has("rotation")) spec.rotation = ReadRotation(node["rotation"]);
  ReadUncertainties(node, &spec);
  return spec;
}

// The factors from the table's length and angle units to mm and rad.
struct TableUnits {
  double to_mm = 1.0;
  double to_rad = 1.0;
};

TableUnits ReadUnits(const ConfigNode& root) {
  const ConfigNode units = Required(root, "units",
                                    "Say the table's units: units: {length: m, "
                                    "angle: deg} (mm or m, rad or deg)");
  units.ExpectMap();
  units.ExpectKeys({"length", "angle"});
  TableUnits out;
  out.to_mm = LengthToMm(Required(units, "length", "Add length: mm or length: m"));
  out.to_rad = AngleToRad(Required(units, "angle", "Add angle: rad or angle: deg"));
  return out;
}

// robot: its name as the job will give it, its joint columns in joint order, and their angle
// unit where it is not the table's.
void ReadRobot(const ConfigNode& root, const TableUnits& units, ImportMapping* m) {
  const ConfigNode robot = Required(root, "robot",
                                    "Say which robot the joints are: robot: {name: "
                                    "ur3, joints: [q1, q2, q3, q4, q5, q6]}");
  robot.ExpectMap();
  robot.ExpectKeys({"name", "joints", "angle"});
  m->robot =
      Required(robot, "name", "Name the robot as the job will (robot: {name: ur3})").AsString();
  if (m->robot == kWorldCarrier || m->robot.find_first_of(",\"\n ") != std::string::npos) {
    throw robot["name"].Error("'" + m->robot + "' cannot name a robot",
                              "Choose a plain name without spaces, not 'world'");
  }
  const ConfigNode joints = Required(robot, "joints",
                                     "List the joint readings' columns in joint "
                                     "order: joints: [q1, q2, q3, q4, q5, q6]");
  if (!joints.IsSequence() || joints.Elements().empty()) {
    throw joints.Error("expected a list of column names", "joints: [q1, q2, q3, q4, q5, q6]");
  }
  for (const auto& j : joints.Elements()) m->joints.push_back(Column(j));
  m->joint_to_rad = robot.Has("angle") ? AngleToRad(robot["angle"]) : units.to_rad;
}

// samples: the column that ties one capture's rows together.
void ReadSamples(const ConfigNode& samples, ImportMapping* m) {
  samples.ExpectMap();
  samples.ExpectKeys({"column"});
  m->sample_column = Column(Required(samples, "column",
                                     "Name the column that ties a sample's "
                                     "rows together: samples: {column: capture}"));
}

// poses: how repeated captures of one pose are found, by a column or by unchanged joints.
void ReadPoses(const ConfigNode& poses, ImportMapping* m) {
  poses.ExpectMap();
  poses.ExpectKeys({"column", "consecutive_joints"});
  if (poses.Has("column") == poses.Has("consecutive_joints")) {
    throw poses.Error("give one way to find repeated poses",
                      "poses: {column: pose} (a column naming the commanded pose) or poses: "
                      "{consecutive_joints: 0} (consecutive samples with the same joints, "
                      "within this many rad)");
  }
  if (poses.Has("column")) {
    m->poses = PoseGrouping::kColumn;
    m->pose_column = Column(poses["column"]);
  } else {
    m->poses = PoseGrouping::kConsecutiveJoints;
    m->pose_joint_tolerance_rad =
        poses.GetDoubleIn("consecutive_joints", 0.0, 0.0, 0.1,
                          "The largest joint difference (rad) between captures of one pose");
  }
}

// targets: each target's name and what carries it (the robot or the world).
void ReadTargets(const ConfigNode& root, ImportMapping* m) {
  const ConfigNode targets = Required(root, "targets",
                                      "List the targets and what carries each: "
                                      "targets: {tool: {on: " +
                                          m->robot + "}, world: {on: world}}");
  for (const auto& name : targets.Keys()) {
    const ConfigNode target = targets[name];
    target.ExpectMap();
    target.ExpectKeys({"on"});
    const ConfigNode on =
        Required(target, "on", "Say what carries it: on: " + m->robot + " or on: world");
    const std::string carrier = on.AsString();
    if (carrier != m->robot && carrier != kWorldCarrier) {
      throw on.Error(
          "target '" + name + "' is on '" + carrier + "', neither the robot nor the world",
          "Write on: " + m->robot + " (carried by the robot) or on: world (fixed)");
    }
    if (name.find_first_of(",\"\n") != std::string::npos) {
      throw target.Error("a target name may not hold ',' '\"' or a line break", "Rename it");
    }
    m->targets.emplace_back(name, carrier);
  }
}

// observations: one entry per (camera, target) pose a row holds.
void ReadObservations(const ConfigNode& root, const TableUnits& units, ImportMapping* m) {
  const ConfigNode observations = Required(root, "observations",
                                           "List what each row observed: observations: [{camera: "
                                           "cam1, target: tool, position: [x, y, z], rotation: "
                                           "{...}}]");
  if (!observations.IsSequence() || observations.Elements().empty()) {
    throw observations.Error("expected a list of observations",
                             "One entry per (camera, target) pose a row holds");
  }
  for (const auto& entry : observations.Elements()) {
    m->observations.push_back(ReadObservation(entry, *m, units.to_mm, units.to_rad));
  }
}

// facts.time: a number in a unit, or a date and time in a format (date_time.h).
FactSpec ReadTimeFact(const ConfigNode& time) {
  if (!time.IsMap() || !time.Has("format")) {
    return ReadFact(time, {"s", "ms", "min", "h"},
                    {{1.0, 0.0}, {1e-3, 0.0}, {60.0, 0.0}, {3600.0, 0.0}});
  }
  if (time.Has("unit")) {
    throw time["unit"].Error("a time with a format is read as seconds: it has no unit",
                             "Drop unit: (or drop format: if the column holds plain numbers)");
  }
  time.ExpectKeys({"table", "column", "format"});
  FactSpec fact;
  fact.column = ColumnOfMap(time, "Name the column: {column: NAME, format: \"%Y-%m-%d %H:%M:%S\"}");
  fact.date_time_format = time["format"].AsString();
  if (const auto problem = DateTimeFormatProblem(fact.date_time_format)) {
    throw time["format"].Error(
        "format '" + fact.date_time_format + "' cannot read a date-time: " + *problem,
        "Write the cells' layout with %Y %m %d %H %M %S, e.g. "
        "\"%d.%m.%Y %H:%M:%S\" for 20.10.2022 16:57:12.092");
  }
  return fact;
}

// facts: the columns of time, temperature and payload, each with its unit.
void ReadFacts(const ConfigNode& facts, ImportMapping* m) {
  facts.ExpectMap();
  facts.ExpectKeys({"time", "temperature", "payload"});
  if (facts.Has("time")) m->time_s = ReadTimeFact(facts["time"]);
  if (facts.Has("temperature")) {
    m->temperature_c = ReadFact(facts["temperature"], {"C", "K"}, {{1.0, 0.0}, {1.0, -273.15}});
  }
  if (facts.Has("payload")) {
    m->payload_kg = ReadFact(facts["payload"], {"kg", "g"}, {{1.0, 0.0}, {1e-3, 0.0}});
  }
}

}  // namespace

std::vector<const ColumnRef*> ImportMapping::AllColumns() const {
  std::vector<const ColumnRef*> all;
  for (const auto& c : joints) all.push_back(&c);
  if (sample_column) all.push_back(&*sample_column);
  if (pose_column) all.push_back(&*pose_column);
  for (const auto& o : observations) {
    if (o.camera.column) all.push_back(&*o.camera.column);
    if (o.target.column) all.push_back(&*o.target.column);
    for (const auto& c : o.position) all.push_back(&c);
    if (o.rotation) {
      for (const auto& c : o.rotation->columns) all.push_back(&c);
    }
    for (const auto& c : o.transform) all.push_back(&c);
    if (o.position_uncertainty) {
      for (const auto& c : o.position_uncertainty->columns) all.push_back(&c);
    }
  }
  for (const auto& t : join.time_s) all.push_back(&t.column);
  for (const auto* fact : {&time_s, &temperature_c, &payload_kg}) {
    if (*fact) all.push_back(&(*fact)->column);
  }
  return all;
}

ImportMapping ReadImportMapping(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectMap();
  root.ExpectKeys({"mapping", "description", "table", "tables", "join", "units", "robot", "samples",
                   "poses", "targets", "observations", "facts"});
  ImportMapping m;
  m.file = path;
  const ConfigNode format = Required(
      root, "mapping", std::string("Start the file with 'mapping: ") + kImportMappingFormat + "'");
  if (format.AsString() != kImportMappingFormat) {
    throw format.Error("unsupported mapping format '" + format.AsString() + "'",
                       std::string("This version reads ") + kImportMappingFormat);
  }
  m.description = root.GetString("description", "");
  import_keys::ReadTables(root, &m);
  const TableUnits units = ReadUnits(root);
  ReadRobot(root, units, &m);
  if (root.Has("samples")) ReadSamples(root["samples"], &m);
  if (root.Has("poses")) ReadPoses(root["poses"], &m);
  ReadTargets(root, &m);
  ReadObservations(root, units, &m);
  if (root.Has("facts")) ReadFacts(root["facts"], &m);
  return m;
}

}  // namespace cellmetry
