// The cellmetry-recording/1 folder (recording.h): read with every cross reference checked and
// converted to mm and rad, and written back in mm and rad with numbers that round-trip exactly.
#include "cellmetry/formats/recording.h"

#include <charconv>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/csv_table.h"
#include "cellmetry/formats/units.h"

namespace cellmetry {
namespace {

// What no camera in a robot cell measures, and no joint reads: beyond these a number is a typo,
// a unit mix-up or a corrupted file, and a fit on it would be garbage with exit 0.
constexpr double kMaxPositionMm = 1e5;    // 100 m from the camera
constexpr double kMaxRotationRad = 10.0;  // a rotation vector is at most pi long
constexpr double kMaxJointRad = 100.0;    // sixteen turns
constexpr int kMaxJoints = 64;            // no arm has more; a count of 2e9 made 2e9 column names

// Rows of samples.csv, observations.csv or images.csv: a fit takes about 5.5 KB per observation
// row, so beyond these it would take more than 1 GB (docs/reliability.md, "Limits on what is
// read"), and the table is refused before a row is parsed.
constexpr size_t kMaxRecordingRows = 150000;

CsvRows RecordingTable(const std::string& path) {
  const std::string limit = std::to_string(kMaxRecordingRows);
  return CsvRows(path, kMaxRecordingRows,
                 "A fit on more would take over 1 GB of memory: thin the recording (keep every "
                 "n-th pose) or split it into recordings of at most " +
                     limit + " rows each");
}

// `column` of the current row, refused with its file, line and column when beyond `max_abs`
// (file units).
double Within(const CsvRows& table, const std::string& column, double max_abs) {
  const double value = table.Number(column);
  if (std::abs(value) > max_abs) {
    char limit[32];
    std::snprintf(limit, sizeof(limit), "%g", max_abs);
    throw table.Error(column,
                      "'" + std::to_string(value) +
                          "' is beyond any measurement of it (|value| <= " + limit +
                          " in this file's units)",
                      "Fix the value, or check the units declared in recording.yaml");
  }
  return value;
}

// recording.yaml must say its units (docs/formats.md): no silent default.
Units ReadRecordingUnits(const ConfigNode& root) {
  if (!root.Has("units")) {
    throw root.Error("missing key 'units'", "Add 'units: {length: mm, angle: rad}'");
  }
  return ReadUnits(root["units"]);
}
// `cameras: [cam1, {name: wrist, on: ur3}]`: a name stands still; `on: <robot>` rides on that
// robot's flange (eye in hand). Robots are read first, so the carrier can be checked here.
void ReadCameraList(const ConfigNode& cameras, Recording* recording) {
  cameras.ExpectSequence();
  for (const ConfigNode& entry : cameras.Elements()) {
    if (!entry.IsMap()) {
      recording->cameras.push_back(entry.AsString());
      continue;
    }
    entry.ExpectKeys({"name", "on"});
    const std::string name = entry["name"].AsString();
    recording->cameras.push_back(name);
    if (!entry.Has("on")) continue;
    const std::string carrier = entry["on"].AsString();
    if (carrier == kWorldCarrier) continue;  // standing still, said in words
    if (!recording->robots.count(carrier)) {
      throw entry["on"].Error("camera '" + name + "' is on unknown robot '" + carrier + "'",
                              "Use 'world' (a camera standing still) or a robot listed under "
                              "'robots'");
    }
    recording->camera_mounts[name] = carrier;
  }
}

void ReadHeader(const std::string& path, Recording* recording, Units* units) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"format", "description", "units", "robots", "cameras", "targets"});
  const std::string format = root["format"].AsString();
  if (format != kRecordingFormat) {
    throw root["format"].Error("unsupported format '" + format + "'",
                               std::string("This version reads ") + kRecordingFormat);
  }
  recording->description = root.GetString("description", "");
  *units = ReadRecordingUnits(root);
  const ConfigNode robots = root["robots"];
  for (const auto& name : robots.Keys()) {
    const ConfigNode robot = robots[name];
    robot.ExpectKeys({"joints"});
    const int joints = robot["joints"].AsInt();
    // Bounded where it is read: samples.csv's columns q1..qN are made from it.
    if (joints < 1 || joints > kMaxJoints) {
      throw robot["joints"].Error("joint count must be between 1 and " + std::to_string(kMaxJoints),
                                  "Give the robot's number of joints");
    }
    recording->robots[name] = joints;
  }
  ReadCameraList(root["cameras"], recording);
  for (size_t i = 1; i < recording->cameras.size(); ++i) {
    const auto end = recording->cameras.begin() + static_cast<long>(i);
    if (std::find(recording->cameras.begin(), end, recording->cameras[i]) != end) {
      throw root["cameras"].Elements()[i].Error(
          "camera '" + recording->cameras[i] + "' is listed twice", "List each camera once");
    }
  }
  const ConfigNode targets = root["targets"];
  for (const auto& name : targets.Keys()) {
    const ConfigNode target = targets[name];
    target.ExpectKeys({"on"});
    const std::string carrier = target["on"].AsString();
    if (carrier != kWorldCarrier && !recording->robots.count(carrier)) {
      throw target["on"].Error("target '" + name + "' is on unknown robot '" + carrier + "'",
                               "Use 'world' or a robot listed under 'robots'");
    }
    recording->targets[name] = carrier;
  }
}

// Captures of one commanded pose share its pose id, and the spread of their readings is the
// robot's repeatability: a sample whose joints differ from its pose's first capture by more than
// any repeat does (kPoseRepeatRad) says another pose, and would pass pose-to-pose differences off
// as repeatability.
constexpr double kPoseRepeatRad = 0.01;

void CheckPoseRepeats(const CsvRows& table, const Sample& sample, const Recording& recording,
                      std::map<std::pair<std::string, int>, size_t>* first_of_pose) {
  const auto [first, inserted] =
      first_of_pose->insert({{sample.robot, sample.pose}, recording.samples.size()});
  if (inserted) return;
  const Sample& earlier = recording.samples[first->second];
  for (size_t j = 0; j < sample.q.size() && j < earlier.q.size(); ++j) {
    if (std::abs(sample.q[j] - earlier.q[j]) <= kPoseRepeatRad) continue;
    char text[200];
    std::snprintf(text, sizeof text,
                  "sample %d repeats pose %d of sample %d (line %d), but its q%zu differs by "
                  "%.3g rad",
                  sample.id, sample.pose, earlier.id, earlier.line, j + 1,
                  std::abs(sample.q[j] - earlier.q[j]));
    throw table.Error("pose", text,
                      "Give each commanded pose its own pose id; captures of one pose share it");
  }
}

void ReadSamples(const std::string& path, const Units& units, Recording* recording) {
  CsvRows table = RecordingTable(path);
  table.RequireColumns({"sample", "robot", "pose"});
  int max_joints = 0;
  for (const auto& [name, joints] : recording->robots) max_joints = std::max(max_joints, joints);
  std::vector<std::string> known = {"sample", "robot", "pose", "t", "temperature", "payload"};
  for (int j = 1; j <= max_joints; ++j) known.push_back("q" + std::to_string(j));
  table.RejectUnknownColumns(known);
  std::set<int> seen;
  std::map<std::pair<std::string, int>, size_t> first_of_pose;  // (robot, pose) -> its first row
  recording->samples.reserve(table.num_rows());
  while (table.Next()) {
    Sample sample;
    sample.line = table.line();
    sample.id = table.Integer("sample");
    if (!seen.insert(sample.id).second) {
      throw table.Error("sample", "sample " + std::to_string(sample.id) + " appears twice",
                        "Give every captured state its own sample id");
    }
    sample.robot = table.Text("robot");
    const auto robot = recording->robots.find(sample.robot);
    if (robot == recording->robots.end()) {
      throw table.Error("robot", "unknown robot '" + sample.robot + "'",
                        "List it under 'robots' in recording.yaml");
    }
    sample.pose = table.Integer("pose");
    for (int j = 1; j <= max_joints; ++j) {
      const std::string column = "q" + std::to_string(j);
      const bool present = table.HasValue(column);
      if (j <= robot->second && !present) {
        throw table.Error(column,
                          "robot '" + sample.robot + "' has " + std::to_string(robot->second) +
                              " joints but this sample has no " + column,
                          "Give one joint value per joint");
      }
      if (j > robot->second && present) {
        throw table.Error(
            column,
            "robot '" + sample.robot + "' has only " + std::to_string(robot->second) + " joints",
            "Leave " + column + " empty for this robot or fix its joint count");
      }
      if (present)
        sample.q.push_back(Within(table, column, kMaxJointRad / units.to_rad) * units.to_rad);
    }
    CheckPoseRepeats(table, sample, *recording, &first_of_pose);
    sample.time_s = table.OptionalNumber("t");
    sample.temperature_c = table.OptionalNumber("temperature");
    sample.payload_kg = table.OptionalNumber("payload");
    recording->samples.push_back(std::move(sample));
  }
}

std::vector<std::string> CovarianceColumns(const std::string& prefix) {
  std::vector<std::string> columns;
  for (const char* entry : {"xx", "xy", "xz", "yy", "yz", "zz"}) columns.push_back(prefix + entry);
  return columns;
}

// A symmetric 3x3 covariance given by its upper triangle (prefix xx, xy, xz, yy, yz, zz), in the
// file's units squared; none when the columns are absent or the row leaves them empty.
std::optional<Eigen::Matrix3d> ReadCovariance(const CsvRows& table, const std::string& prefix,
                                              double scale) {
  const std::vector<std::string> columns = CovarianceColumns(prefix);
  for (const auto& c : columns) {
    if (!table.HasColumn(c)) return std::nullopt;
  }
  if (!table.HasValue(columns[0])) return std::nullopt;
  const auto v = [&](int i) { return table.Number(columns[i]); };
  Eigen::Matrix3d c;
  c << v(0), v(1), v(2), v(1), v(3), v(4), v(2), v(4), v(5);
  return c * scale;
}

// An observation row's sample, camera and target, each one the recording lists.
void ReadObservationNames(CsvRows& table, const Recording& recording,
                          const std::set<int>& sample_ids, Observation* obs) {
  obs->sample = table.Integer("sample");
  if (!sample_ids.count(obs->sample)) {
    throw table.Error("sample", "unknown sample " + std::to_string(obs->sample),
                      "Every observation must name a sample listed in samples.csv");
  }
  obs->camera = table.Text("camera");
  if (!recording.HasCamera(obs->camera)) {
    throw table.Error("camera", "unknown camera '" + obs->camera + "'",
                      "List it under 'cameras' in recording.yaml");
  }
  obs->target = table.Text("target");
  if (!recording.targets.count(obs->target)) {
    throw table.Error("target", "unknown target '" + obs->target + "'",
                      "List it under 'targets' in recording.yaml");
  }
}

// An observation row's position, its rotation where all three cells are filled, and their
// covariances, in mm and rad.
void ReadObservationPose(CsvRows& table, const Units& units, bool has_rotation, Observation* obs) {
  obs->position_mm = Eigen::Vector3d(Within(table, "x", kMaxPositionMm / units.to_mm),
                                     Within(table, "y", kMaxPositionMm / units.to_mm),
                                     Within(table, "z", kMaxPositionMm / units.to_mm)) *
                     units.to_mm;
  if (has_rotation) {
    const int filled = table.HasValue("rx") + table.HasValue("ry") + table.HasValue("rz");
    if (filled == 3) {
      obs->rvec = Eigen::Vector3d(Within(table, "rx", kMaxRotationRad / units.to_rad),
                                  Within(table, "ry", kMaxRotationRad / units.to_rad),
                                  Within(table, "rz", kMaxRotationRad / units.to_rad)) *
                  units.to_rad;
    } else if (filled != 0) {
      throw table.Error("rx", "rotation is partly filled in",
                        "Give all of rx,ry,rz or leave all three empty");
    }
  }
  obs->covariance_mm2 = ReadCovariance(table, "cov_", units.to_mm * units.to_mm);
  obs->rotation_covariance_rad2 = ReadCovariance(table, "rcov_", units.to_rad * units.to_rad);
}

void ReadObservations(const std::string& path, const Units& units, Recording* recording,
                      bool allow_empty) {
  CsvRows table = RecordingTable(path);
  table.RequireColumns({"sample", "camera", "target", "x", "y", "z"});
  std::vector<std::string> known = {"sample", "camera", "target", "x", "y", "z", "rx", "ry", "rz"};
  for (const char* prefix : {"cov_", "rcov_"}) {
    for (const auto& column : CovarianceColumns(prefix)) known.push_back(column);
  }
  table.RejectUnknownColumns(known);
  const bool has_rotation = table.HasColumn("rx") && table.HasColumn("ry") && table.HasColumn("rz");
  std::set<int> sample_ids;
  for (const auto& s : recording->samples) sample_ids.insert(s.id);
  // A row given twice weighs twice in the fit, without a word (found by test_bad_input).
  std::map<std::tuple<int, std::string, std::string>, int> first_line;
  recording->observations.reserve(table.num_rows());
  while (table.Next()) {
    Observation obs;
    obs.line = table.line();
    ReadObservationNames(table, *recording, sample_ids, &obs);
    const auto [first, fresh] = first_line.insert({{obs.sample, obs.camera, obs.target}, obs.line});
    if (!fresh) {
      throw table.Error("target",
                        "target '" + obs.target + "' in sample " + std::to_string(obs.sample) +
                            " by camera '" + obs.camera + "' was already given on line " +
                            std::to_string(first->second),
                        "Keep one row per sample, camera and target");
    }
    ReadObservationPose(table, units, has_rotation, &obs);
    recording->observations.push_back(std::move(obs));
  }
  if (recording->observations.empty() && !allow_empty) {
    throw InputError({path, 0, 0}, "no observations",
                     "A recording needs at least one measured target pose");
  }
}

void ReadImages(const std::string& path, Recording* recording) {
  CsvRows table = RecordingTable(path);
  table.RequireColumns({"sample", "camera", "view", "path"});
  table.RejectUnknownColumns({"sample", "camera", "view", "path"});
  while (table.Next()) {
    ImageRef image;
    image.sample = table.Integer("sample");
    if (recording->SampleIndex(image.sample) < 0) {
      throw table.Error("sample", "unknown sample " + std::to_string(image.sample),
                        "Every image must name a sample listed in samples.csv");
    }
    image.camera = table.Text("camera");
    if (!recording->HasCamera(image.camera)) {
      throw table.Error("camera", "unknown camera '" + image.camera + "'",
                        "List it under 'cameras' in recording.yaml");
    }
    image.view = table.Text("view");
    if (image.view != "left" && image.view != "right" && image.view != "mono") {
      throw table.Error("view", "unknown view '" + image.view + "'", "Use left, right or mono");
    }
    image.path = table.Text("path");
    recording->images.push_back(std::move(image));
  }
}

// Shortest text that reads back to the same double (simulated truth must round-trip exactly).
std::string Number(double value) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof(buffer), value).ptr;
  return std::string(buffer, end);
}

void WriteCovariance(const std::optional<Eigen::Matrix3d>& covariance, std::ostream& out) {
  if (!covariance) {
    out << ",,,,,,";
    return;
  }
  const Eigen::Matrix3d& c = *covariance;
  for (const auto& [i, k] : {std::pair{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}}) {
    out << "," << Number(c(i, k));
  }
}

}  // namespace

std::string ObservationsCsv(const std::vector<Observation>& list) {
  const bool any_covariance = std::any_of(
      list.begin(), list.end(), [](const Observation& o) { return o.covariance_mm2.has_value(); });
  const bool any_rotation_covariance =
      std::any_of(list.begin(), list.end(),
                  [](const Observation& o) { return o.rotation_covariance_rad2.has_value(); });
  std::ostringstream out;
  out << "sample,camera,target,x,y,z,rx,ry,rz";
  if (any_covariance) {
    for (const auto& c : CovarianceColumns("cov_")) out << "," << c;
  }
  if (any_rotation_covariance) {
    for (const auto& c : CovarianceColumns("rcov_")) out << "," << c;
  }
  out << "\n";
  for (const auto& o : list) {
    out << o.sample << "," << o.camera << "," << o.target << "," << Number(o.position_mm.x()) << ","
        << Number(o.position_mm.y()) << "," << Number(o.position_mm.z());
    if (o.rvec) {
      out << "," << Number(o.rvec->x()) << "," << Number(o.rvec->y()) << "," << Number(o.rvec->z());
    } else {
      out << ",,,";
    }
    if (any_covariance) WriteCovariance(o.covariance_mm2, out);
    if (any_rotation_covariance) WriteCovariance(o.rotation_covariance_rad2, out);
    out << "\n";
  }
  return out.str();
}

int Recording::SampleIndex(int id) const {
  // Samples are usually numbered 0..n-1 in order; try the direct hit first.
  if (id >= 0 && id < static_cast<int>(samples.size()) && samples[id].id == id) return id;
  for (size_t i = 0; i < samples.size(); ++i) {
    if (samples[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

bool Recording::HasCamera(const std::string& name) const {
  return std::find(cameras.begin(), cameras.end(), name) != cameras.end();
}

bool Recording::IsCarried(const std::string& target) const {
  const auto it = targets.find(target);
  return it != targets.end() && it->second != kWorldCarrier;
}

Recording ReadRecording(const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code unreadable;  // e.g. a name too long: "not a recording", not a throw
  if (!fs::is_directory(folder, unreadable)) {
    throw InputError({folder, 0, 0}, "recording folder not found",
                     "Give the folder that holds recording.yaml, samples.csv, observations.csv");
  }
  Recording recording;
  recording.folder = folder;
  Units units;
  ReadHeader(folder + "/recording.yaml", &recording, &units);
  ReadSamples(folder + "/samples.csv", units, &recording);
  const bool has_images = fs::exists(folder + "/images.csv");
  // A recording of images has no observations until `cellmetry detect` writes them.
  if (!has_images || fs::exists(folder + "/observations.csv")) {
    // Detection may have found nothing yet in a recording of images.
    ReadObservations(folder + "/observations.csv", units, &recording, /*allow_empty=*/has_images);
  }
  if (has_images) ReadImages(folder + "/images.csv", &recording);
  return recording;
}

namespace {

// recording.yaml: format, description, units, robots with their joint counts, cameras (with
// their mount where one rides on a robot) and targets with their carriers.
std::string HeaderYaml(const Recording& recording) {
  YAML::Emitter header;
  header << YAML::BeginMap << YAML::Key << "format" << YAML::Value << kRecordingFormat;
  header << YAML::Key << "description" << YAML::Value << recording.description;
  header << YAML::Key << "units" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
         << "length" << YAML::Value << "mm" << YAML::Key << "angle" << YAML::Value << "rad"
         << YAML::EndMap;
  header << YAML::Key << "robots" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, joints] : recording.robots) {
    header << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
           << "joints" << YAML::Value << joints << YAML::EndMap;
  }
  header << YAML::EndMap << YAML::Key << "cameras" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const auto& camera : recording.cameras) {
    const auto mount = recording.camera_mounts.find(camera);
    if (mount == recording.camera_mounts.end()) {
      header << camera;
    } else {
      header << YAML::BeginMap << YAML::Key << "name" << YAML::Value << camera << YAML::Key << "on"
             << YAML::Value << mount->second << YAML::EndMap;
    }
  }
  header << YAML::EndSeq;
  header << YAML::Key << "targets" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, carrier] : recording.targets) {
    header << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "on"
           << YAML::Value << carrier << YAML::EndMap;
  }
  header << YAML::EndMap << YAML::EndMap;
  return std::string(header.c_str()) + "\n";
}

// samples.csv: a joint column for each joint of the robot with the most, and the time,
// temperature and payload columns where any sample has one (an empty cell where it has none).
std::string SamplesCsv(const Recording& recording) {
  int max_joints = 0;
  for (const auto& [name, joints] : recording.robots) max_joints = std::max(max_joints, joints);
  bool has_t = false, has_temperature = false, has_payload = false;
  for (const auto& s : recording.samples) {
    has_t |= s.time_s.has_value();
    has_temperature |= s.temperature_c.has_value();
    has_payload |= s.payload_kg.has_value();
  }
  std::ostringstream samples;
  samples << "sample,robot,pose";
  for (int j = 1; j <= max_joints; ++j) samples << ",q" << j;
  if (has_t) samples << ",t";
  if (has_temperature) samples << ",temperature";
  if (has_payload) samples << ",payload";
  samples << "\n";
  auto optional = [](const std::optional<double>& v) { return v ? Number(*v) : std::string(); };
  for (const auto& s : recording.samples) {
    samples << s.id << "," << s.robot << "," << s.pose;
    for (int j = 0; j < max_joints; ++j) {
      samples << "," << (j < static_cast<int>(s.q.size()) ? Number(s.q[j]) : "");
    }
    if (has_t) samples << "," << optional(s.time_s);
    if (has_temperature) samples << "," << optional(s.temperature_c);
    if (has_payload) samples << "," << optional(s.payload_kg);
    samples << "\n";
  }
  return samples.str();
}

std::string ImagesCsv(const std::vector<ImageRef>& list) {
  std::ostringstream images;
  images << "sample,camera,view,path\n";
  for (const auto& i : list) {
    images << i.sample << "," << i.camera << "," << i.view << "," << i.path << "\n";
  }
  return images.str();
}

}  // namespace

void WriteRecording(const Recording& recording, const std::string& folder,
                    const std::string& truth_yaml,
                    const std::function<void(const std::string&)>& write_extra) {
  StagedDirectory out(folder, "recording");
  AtomicWriteFile(out.File("recording.yaml"), HeaderYaml(recording));
  AtomicWriteFile(out.File("samples.csv"), SamplesCsv(recording));
  if (!recording.observations.empty()) {
    AtomicWriteFile(out.File("observations.csv"), ObservationsCsv(recording.observations));
  }
  if (!recording.images.empty())
    AtomicWriteFile(out.File("images.csv"), ImagesCsv(recording.images));
  if (!truth_yaml.empty()) AtomicWriteFile(out.File("truth.yaml"), truth_yaml);
  if (write_extra) write_extra(out.staging());
  out.Commit();
}

}  // namespace cellmetry
