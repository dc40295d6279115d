// Reading result.json back (workcell_result_file.h).
#include "cellmetry/formats/workcell_result_file.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

using nlohmann::json;

const char kRunAgain[] = "Give the folder `cellmetry run` wrote";

// A value of the file with the key path that leads to it, so that every complaint names the
// file and the key: "malformed result: frames.tool.xyz_mm[2]: expected a number".
class Entry {
 public:
  Entry(const json& value, std::string key_path, const std::string& file)
      : value_(value), key_path_(std::move(key_path)), file_(file) {}

  bool Has(const std::string& key) const { return value_.is_object() && value_.contains(key); }

  Entry operator[](const std::string& key) const {
    if (!value_.is_object()) Fail("expected an object");
    const auto found = value_.find(key);
    if (found == value_.end()) Fail("no '" + key + "'");
    return Entry(*found, Child(key), file_);
  }

  // An object's entries in key order (nlohmann::json keeps an object's keys sorted).
  template <typename Read>
  void ForEachKey(const Read& read) const {
    if (!value_.is_object()) Fail("expected an object");
    for (const auto& [key, value] : value_.items()) read(key, Entry(value, Child(key), file_));
  }

  template <typename Read>
  void ForEachElement(const Read& read) const {
    if (!value_.is_array()) Fail("expected a list");
    for (size_t i = 0; i < value_.size(); ++i) read(At(i));
  }

  double Number() const {
    if (!value_.is_number()) Fail("expected a number");
    return value_.get<double>();
  }
  // A number, or nothing where the file has null (held, or not a number when written).
  std::optional<double> NumberOrNull() const {
    if (value_.is_null()) return std::nullopt;
    return Number();
  }
  std::string Text() const {
    if (!value_.is_string()) Fail("expected a string");
    return value_.get<std::string>();
  }
  bool Flag() const {
    if (!value_.is_boolean()) Fail("expected true or false");
    return value_.get<bool>();
  }
  Eigen::Vector3d Vector3() const {
    if (!value_.is_array() || value_.size() != 3) Fail("expected 3 numbers");
    return Eigen::Vector3d(At(0).Number(), At(1).Number(), At(2).Number());
  }
  // Three numbers, each of which may be null.
  std::array<std::optional<double>, 3> Vector3OrNulls() const {
    if (!value_.is_array() || value_.size() != 3) Fail("expected 3 numbers or nulls");
    return {At(0).NumberOrNull(), At(1).NumberOrNull(), At(2).NumberOrNull()};
  }
  std::vector<double> Numbers() const {
    std::vector<double> numbers;
    ForEachElement([&](const Entry& e) { numbers.push_back(e.Number()); });
    return numbers;
  }
  std::vector<std::string> Texts() const {
    std::vector<std::string> texts;
    ForEachElement([&](const Entry& e) { texts.push_back(e.Text()); });
    return texts;
  }

  [[noreturn]] void Fail(const std::string& what) const {
    const std::string where = key_path_.empty() ? "" : key_path_ + ": ";
    throw InputError({file_, 0, 0}, "malformed result: " + where + what,
                     std::string(kRunAgain) + ", unedited");
  }

 private:
  Entry At(size_t i) const {
    return Entry(value_[i], key_path_ + "[" + std::to_string(i) + "]", file_);
  }
  std::string Child(const std::string& key) const {
    return key_path_.empty() ? key : key_path_ + "." + key;
  }

  const json& value_;
  std::string key_path_;
  const std::string& file_;
};

// xyz_mm, rvec_rad, sigma_xyz_mm and sigma_rot_rad: a frame's pose and its sigma.
CalibratedFrame ReadFrame(const std::string& name, const std::string& parent, const Entry& e) {
  CalibratedFrame frame;
  frame.name = name;
  frame.parent = parent;
  frame.T_parent_frame = PoseFromRvecT(e["rvec_rad"].Vector3(), e["xyz_mm"].Vector3());
  const auto sigma_xyz = e["sigma_xyz_mm"].Vector3OrNulls();
  const auto sigma_rot = e["sigma_rot_rad"].Vector3OrNulls();
  for (int i = 0; i < 3; ++i) {
    frame.sigma[i] = sigma_xyz[i];
    frame.sigma[3 + i] = sigma_rot[i];
  }
  return frame;
}

FittedScalar ReadScalar(const Entry& e) {
  return {e["name"].Text(), e["unit"].Text(), e["value"].Number(), e["sigma"].NumberOrNull(),
          e["held"].Flag()};
}

ResultRobotModel ReadRobotModel(const std::string& robot, const Entry& e) {
  ResultRobotModel model{robot, e["model_file"].Text(), e["model_config"].Text(), {}, {}};
  e["model_values"].ForEachElement([&](const Entry& value) {
    model.model_values.emplace_back(value["name"].Text(), value["value"].Number());
  });
  if (!e.Has("joint_ranges_rad")) return model;
  e["joint_ranges_rad"].ForEachElement([&](const Entry& range) {
    const std::vector<double> min_max = range.Numbers();
    if (min_max.size() != 2 || min_max[0] > min_max[1]) {
      range.Fail("expected [min, max] with min <= max");
    }
    model.joint_ranges_rad.emplace_back(min_max[0], min_max[1]);
  });
  return model;
}

ResultUnidentifiable ReadUnidentifiable(const Entry& e) {
  ResultUnidentifiable u{e["name"].Text(), {}};
  if (!e.Has("moves_with")) return u;
  e["moves_with"].ForEachElement([&](const Entry& partner) {
    u.moves_with.push_back({partner["name"].Text(), partner["ratio"].Number()});
  });
  return u;
}

// Every section the readers take, in the file's terms; `root` is a cellmetry-result/1 object.
void ReadSections(const Entry& root, WorkcellResultFile* r) {
  root["frames"].ForEachKey([&](const std::string& name, const Entry& frame) {
    r->frames.push_back(ReadFrame(name, frame["parent"].Text(), frame));
  });
  root["model_parameters"].ForEachElement(
      [&](const Entry& p) { r->model_parameters.push_back(ReadScalar(p)); });
  r->records_robots = root.Has("robots");
  if (r->records_robots) {
    root["robots"].ForEachKey([&](const std::string& robot, const Entry& model) {
      r->robots.push_back(ReadRobotModel(robot, model));
    });
  }
  if (root.Has("robot_to_robot")) {
    root["robot_to_robot"].ForEachKey([&](const std::string& key, const Entry& pair) {
      r->robot_to_robot.push_back(
          {key, ReadFrame(pair["frame"].Text(), pair["parent"].Text(), pair)});
    });
  }
  if (root.Has("effects")) {
    root["effects"].ForEachKey([&](const std::string& name, const Entry& e) {
      r->effects.push_back(
          {name, e["robot"].Text(), e["type"].Text(), e["stage"].Text(), e["config"].Text()});
    });
  }
  if (root.Has("unidentifiable")) {
    root["unidentifiable"].ForEachElement(
        [&](const Entry& u) { r->unidentifiable.push_back(ReadUnidentifiable(u)); });
  }
  if (root.Has("gravity_base_m_s2")) r->gravity_base_m_s2 = root["gravity_base_m_s2"].Vector3();
  r->free_parameters = root["free_parameters"].Texts();
  r->sigma = root["sigma"].Numbers();
  root["correlation"].ForEachElement(
      [&](const Entry& row) { r->correlation.push_back(row.Numbers()); });
}

}  // namespace

WorkcellResultFile ParseWorkcellResult(const std::string& text, const std::string& origin) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw InputError({origin, 0, 0}, std::string("not a result file: ") + e.what(), kRunAgain);
  }
  const auto format = j.is_object() ? j.find("format") : j.end();
  if (format == j.end() || *format != "cellmetry-result/1") {
    throw InputError({origin, 0, 0}, "not a cellmetry result (format is not cellmetry-result/1)",
                     kRunAgain);
  }
  WorkcellResultFile result;
  result.path = origin;
  ReadSections(Entry(j, "", origin), &result);
  return result;
}

WorkcellResultFile ReadWorkcellResult(const std::string& json_path) {
  std::ifstream in(json_path);
  if (!in) {
    throw InputError({json_path, 0, 0}, "cannot open the result",
                     "Give the folder `cellmetry run` wrote (its `output:`)");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return ParseWorkcellResult(text.str(), json_path);
}

}  // namespace cellmetry
