// Reading a result folder for exports (calibrated_cell.h).
#include "cellmetry/exports/calibrated_cell.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

using nlohmann::json;

const char kRerun[] = "Run the job again with this cellmetry to write a result it can export";

Eigen::Vector3d Vector(const json& values) {
  return Eigen::Vector3d(values.at(0).get<double>(), values.at(1).get<double>(),
                         values.at(2).get<double>());
}

std::optional<double> Sigma(const json& value) {
  if (value.is_null()) return std::nullopt;
  return value.get<double>();
}

CalibratedFrame ReadFrame(const std::string& name, const json& j) {
  CalibratedFrame frame;
  frame.name = name;
  frame.parent = j.at("parent").get<std::string>();
  frame.T_parent_frame = PoseFromRvecT(Vector(j.at("rvec_rad")), Vector(j.at("xyz_mm")));
  for (int i = 0; i < 3; ++i) {
    frame.sigma[i] = Sigma(j.at("sigma_xyz_mm").at(i));
    frame.sigma[3 + i] = Sigma(j.at("sigma_rot_rad").at(i));
  }
  return frame;
}

FittedScalar ReadScalar(const json& j) {
  return {j.at("name").get<std::string>(), j.at("unit").get<std::string>(),
          j.at("value").get<double>(), Sigma(j.at("sigma"))};
}

// The robot's model from its recorded config, at the recorded values.
CalibratedRobot ReadRobot(const std::string& name, const json& j, const std::string& json_path,
                          const Registry& registry) {
  CalibratedRobot robot;
  robot.name = name;
  robot.model_file = j.at("model_file").get<std::string>();
  const std::string text = j.at("model_config").get<std::string>();
  if (text.empty()) {
    throw InputError({json_path, 0, 0}, "the result does not record the config of robot '" +
                     name + "' (the job was built in memory)", kRerun);
  }
  // Named after the config file itself: paths it holds (a urdf robot's `file:`) resolve against
  // its folder, as they did in the run, not against the result's.
  robot.model_config =
      std::make_shared<ConfigNode>(ConfigNode::LoadString(text, robot.model_file));
  robot.model_type = (*robot.model_config)["type"].AsString();
  robot.model = registry.CreateRobotModel(robot.model_type, *robot.model_config);
  const auto& parameters = robot.model->parameters();
  const json& values = j.at("model_values");
  if (values.size() != parameters.size()) {
    throw InputError({json_path, 0, 0}, "robot '" + name + "' records " +
                     std::to_string(values.size()) + " model values, its model '" +
                     robot.model_type + "' has " + std::to_string(parameters.size()) +
                     " parameters", "The plugin changed since the run. " + std::string(kRerun));
  }
  for (size_t i = 0; i < parameters.size(); ++i) {
    const std::string recorded = values[i].at("name").get<std::string>();
    if (recorded != parameters[i].name) {
      throw InputError({json_path, 0, 0}, "robot '" + name + "' records model value '" +
                       recorded + "' where its model has '" + parameters[i].name + "'",
                       "The plugin changed since the run. " + std::string(kRerun));
    }
    robot.values.push_back(values[i].at("value").get<double>());
  }
  return robot;
}

// Model parameters go to their robot, effects to their robot's chain or to the cameras.
void SortScalars(const json& scalars, CalibratedCell* cell) {
  for (const json& entry : scalars) {
    const FittedScalar scalar = ReadScalar(entry);
    bool placed = false;
    for (auto& robot : cell->robots) {
      if (scalar.name.rfind(robot.name + ".model.", 0) == 0) {
        robot.fitted.push_back(scalar);
        placed = true;
      } else if (scalar.name.rfind(robot.name + ".", 0) == 0) {
        robot.effects.push_back(scalar);
        placed = true;
      }
      if (placed) break;
    }
    if (!placed) cell->camera_effects.push_back(scalar);
  }
}

// The scalar called `name` among a robot's and the cameras' fitted scalars, or nullptr.
const FittedScalar* FindScalar(const CalibratedCell& cell, const std::string& name) {
  for (const auto& s : cell.camera_effects) {
    if (s.name == name) return &s;
  }
  for (const auto& robot : cell.robots) {
    for (const auto& s : robot.effects) {
      if (s.name == name) return &s;
    }
  }
  return nullptr;
}

// An effect rebuilt from its recorded block on its robot's model, at its fitted values.
CalibratedEffect ReadEffect(const std::string& name, const json& j, const CalibratedCell& cell,
                            const Registry& registry) {
  CalibratedEffect e;
  e.name = name;
  e.robot = j.at("robot").get<std::string>();
  e.type = j.at("type").get<std::string>();
  e.stage = j.at("stage").get<std::string>();
  const std::string config = j.at("config").get<std::string>();
  if (config.empty()) return e;
  const auto robot = std::find_if(cell.robots.begin(), cell.robots.end(),
                                  [&](const CalibratedRobot& r) { return r.name == e.robot; });
  if (robot == cell.robots.end()) {
    throw InputError({cell.json_path, 0, 0}, "effect '" + name + "' is recorded on robot '" +
                     e.robot + "', which the result does not have", kRerun);
  }
  const ConfigNode node = ConfigNode::LoadString(config, "effect '" + name + "' as recorded in " +
                                                 cell.json_path);
  e.effect = registry.CreateEffect(e.type, node, *robot->model);
  for (const Parameter& p : e.effect->parameters()) {
    const FittedScalar* fitted = FindScalar(cell, name + "." + p.name);
    if (!fitted) {
      throw InputError({cell.json_path, 0, 0}, "effect '" + name + "' has no value for '" +
                       p.name + "' in model_parameters", kRerun);
    }
    e.parameters.push_back(*fitted);
  }
  return e;
}

ParameterCovariance ReadCovariance(const json& j) {
  ParameterCovariance c;
  c.names = j.at("free_parameters").get<std::vector<std::string>>();
  const auto sigma = j.at("sigma").get<std::vector<double>>();
  const auto correlation = j.at("correlation").get<std::vector<std::vector<double>>>();
  const int n = static_cast<int>(c.names.size());
  c.covariance = Eigen::MatrixXd::Zero(n, n);
  if (static_cast<int>(sigma.size()) != n || static_cast<int>(correlation.size()) != n) return c;
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) c.covariance(a, b) = sigma[a] * sigma[b] * correlation[a].at(b);
  }
  return c;
}

}  // namespace

int ParameterCovariance::Find(const std::string& name) const {
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<int>(i);
  }
  return -1;
}

CalibratedCell ReadCalibratedCell(const std::string& result_folder, const Registry& registry) {
  CalibratedCell cell;
  cell.folder = result_folder;
  cell.json_path = (std::filesystem::path(result_folder) / "result.json").string();
  if (!std::filesystem::is_directory(result_folder)) {
    throw InputError({result_folder, 0, 0}, "no such result folder",
                     "Give the folder `cellmetry run` wrote (its `output:`)");
  }
  std::ifstream in(cell.json_path);
  if (!in) {
    throw InputError({cell.json_path, 0, 0}, "cannot open the result",
                     "Give the folder `cellmetry run` wrote (its `output:`)");
  }
  json j;
  try {
    in >> j;
  } catch (const std::exception& e) {
    throw InputError({cell.json_path, 0, 0}, std::string("not a result file: ") + e.what(),
                     "Give the folder `cellmetry run` wrote");
  }
  if (!j.is_object() || j.value("format", "") != "cellmetry-result/1") {
    throw InputError({cell.json_path, 0, 0}, "not a cellmetry result (format is not "
                     "cellmetry-result/1)", "Give the folder `cellmetry run` wrote");
  }
  try {
    for (const auto& [name, frame] : j.at("frames").items()) {
      cell.frames.push_back(ReadFrame(name, frame));
    }
    if (!j.contains("robots")) {
      // Every workcell has a robot; a result without this section predates it.
      throw InputError({cell.json_path, 0, 0}, "the result does not record its robots' models "
                       "(written by an older cellmetry)", kRerun);
    }
    for (const auto& [name, robot] : j.at("robots").items()) {
      cell.robots.push_back(ReadRobot(name, robot, cell.json_path, registry));
    }
    SortScalars(j.at("model_parameters"), &cell);
    if (j.contains("effects")) {
      for (const auto& [name, effect] : j.at("effects").items()) {
        cell.effects.push_back(ReadEffect(name, effect, cell, registry));
      }
    }
    if (j.contains("gravity_base_m_s2")) cell.gravity_base = Vector(j.at("gravity_base_m_s2"));
    cell.covariance = ReadCovariance(j);
  } catch (const json::exception& e) {
    throw InputError({cell.json_path, 0, 0}, std::string("malformed result: ") + e.what(),
                     "Give the folder `cellmetry run` wrote, unedited");
  }
  return cell;
}

const CalibratedFrame* FindFrame(const CalibratedCell& cell, const std::string& name) {
  for (const auto& frame : cell.frames) {
    if (frame.name == name) return &frame;
  }
  return nullptr;
}

const CalibratedRobot& ChooseRobot(const CalibratedCell& cell, const std::string& requested) {
  std::string names;
  for (const auto& robot : cell.robots) names += (names.empty() ? "" : ", ") + robot.name;
  if (cell.robots.empty()) {
    throw InputError({cell.json_path, 0, 0}, "the result has no robot to export",
                     "Export its frames with --format tf");
  }
  if (requested.empty()) {
    if (cell.robots.size() == 1) return cell.robots.front();
    throw InputError({cell.json_path, 0, 0}, "the result has several robots (" + names + ")",
                     "Name one with --robot");
  }
  for (const auto& robot : cell.robots) {
    if (robot.name == requested) return robot;
  }
  throw InputError({cell.json_path, 0, 0}, "the result has no robot '" + requested + "'",
                   "Its robots: " + names);
}

}  // namespace cellmetry
