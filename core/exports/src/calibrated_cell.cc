// Reading a result folder for exports (calibrated_cell.h).
#include "cellmetry/exports/calibrated_cell.h"

#include <algorithm>
#include <filesystem>

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

const char kRerun[] = "Run the job again with this cellmetry to write a result it can export";

// The robot's model from its recorded config, at the recorded values.
CalibratedRobot ReadRobot(const ResultRobotModel& recorded, const std::string& json_path,
                          const Registry& registry) {
  CalibratedRobot robot;
  robot.name = recorded.robot;
  robot.model_file = recorded.model_file;
  if (recorded.model_config.empty()) {
    throw InputError({json_path, 0, 0},
                     "the result does not record the config of robot '" + robot.name +
                         "' (the job was built in memory)",
                     kRerun);
  }
  // Named after the config file itself: paths it holds (a urdf robot's `file:`) resolve against
  // its folder, as they did in the run, not against the result's.
  robot.model_config =
      std::make_shared<ConfigNode>(ConfigNode::LoadString(recorded.model_config, robot.model_file));
  robot.model_type = (*robot.model_config)["type"].AsString();
  robot.model = registry.CreateRobotModel(robot.model_type, *robot.model_config);
  const auto& parameters = robot.model->parameters();
  const auto& values = recorded.model_values;
  if (values.size() != parameters.size()) {
    throw InputError({json_path, 0, 0},
                     "robot '" + robot.name + "' records " + std::to_string(values.size()) +
                         " model values, its model '" + robot.model_type + "' has " +
                         std::to_string(parameters.size()) + " parameters",
                     "The plugin changed since the run. " + std::string(kRerun));
  }
  for (size_t i = 0; i < parameters.size(); ++i) {
    if (values[i].first != parameters[i].name) {
      throw InputError({json_path, 0, 0},
                       "robot '" + robot.name + "' records model value '" + values[i].first +
                           "' where its model has '" + parameters[i].name + "'",
                       "The plugin changed since the run. " + std::string(kRerun));
    }
    robot.values.push_back(values[i].second);
  }
  robot.joint_ranges_rad = recorded.joint_ranges_rad;
  if (!robot.joint_ranges_rad.empty() &&
      robot.joint_ranges_rad.size() != static_cast<size_t>(robot.model->num_joints())) {
    throw InputError(
        {json_path, 0, 0},
        "robot '" + robot.name + "' records " + std::to_string(robot.joint_ranges_rad.size()) +
            " joint ranges, its model has " + std::to_string(robot.model->num_joints()) + " joints",
        kRerun);
  }
  return robot;
}

// Model parameters go to their robot, effects to their robot's chain or to the cameras.
void SortScalars(const std::vector<FittedScalar>& scalars, CalibratedCell* cell) {
  for (const FittedScalar& scalar : scalars) {
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
CalibratedEffect ReadEffect(const ResultEffect& recorded, const CalibratedCell& cell,
                            const Registry& registry) {
  CalibratedEffect e;
  e.name = recorded.name;
  e.robot = recorded.robot;
  e.type = recorded.type;
  e.stage = recorded.stage;
  if (recorded.config.empty()) return e;
  const auto robot = std::find_if(cell.robots.begin(), cell.robots.end(),
                                  [&](const CalibratedRobot& r) { return r.name == e.robot; });
  if (robot == cell.robots.end()) {
    throw InputError({cell.json_path, 0, 0},
                     "effect '" + e.name + "' is recorded on robot '" + e.robot +
                         "', which the result does not have",
                     kRerun);
  }
  const ConfigNode node = ConfigNode::LoadString(
      recorded.config, "effect '" + e.name + "' as recorded in " + cell.json_path);
  e.effect = registry.CreateEffect(e.type, node, *robot->model);
  for (const Parameter& p : e.effect->parameters()) {
    const FittedScalar* fitted = FindScalar(cell, e.name + "." + p.name);
    if (!fitted) {
      throw InputError(
          {cell.json_path, 0, 0},
          "effect '" + e.name + "' has no value for '" + p.name + "' in model_parameters", kRerun);
    }
    e.parameters.push_back(*fitted);
  }
  return e;
}

ParameterCovariance Covariance(const WorkcellResultFile& result) {
  ParameterCovariance c;
  c.names = result.free_parameters;
  const auto& sigma = result.sigma;
  const auto& correlation = result.correlation;
  const int n = static_cast<int>(c.names.size());
  c.covariance = Eigen::MatrixXd::Zero(n, n);
  // A run writes one sigma and one correlation row per free parameter; anything else is an
  // edited file whose covariance would come out zero or wrong, so it is refused.
  const auto refuse_size = [&](const std::string& key, size_t entries) {
    if (static_cast<int>(entries) == n) return;
    throw InputError({result.path, 0, 0},
                     "malformed result: " + key + " has " + std::to_string(entries) +
                         " entries for " + std::to_string(n) + " free parameters",
                     "Give the folder `cellmetry run` wrote, unedited");
  };
  refuse_size("sigma", sigma.size());
  refuse_size("correlation", correlation.size());
  for (int a = 0; a < n; ++a) {
    refuse_size("correlation[" + std::to_string(a) + "]", correlation[a].size());
    for (int b = 0; b < n; ++b) c.covariance(a, b) = sigma[a] * sigma[b] * correlation[a][b];
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
  const WorkcellResultFile result = ReadWorkcellResult(cell.json_path);
  cell.frames = result.frames;
  if (!result.records_robots) {
    // Every workcell has a robot; a result without this section predates it.
    throw InputError({cell.json_path, 0, 0},
                     "the result does not record its robots' models "
                     "(written by an older cellmetry)",
                     kRerun);
  }
  for (const ResultRobotModel& robot : result.robots) {
    cell.robots.push_back(ReadRobot(robot, cell.json_path, registry));
  }
  SortScalars(result.model_parameters, &cell);
  for (const ResultEffect& effect : result.effects) {
    cell.effects.push_back(ReadEffect(effect, cell, registry));
  }
  if (result.gravity_base_m_s2) cell.gravity_base = *result.gravity_base_m_s2;
  cell.covariance = Covariance(result);
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
