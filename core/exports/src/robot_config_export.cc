// The calibrated robot as a cellmetry robot config (robot_config_export.h).
#include "cellmetry/exports/robot_config_export.h"

#include <stdexcept>

#include "cellmetry/basics/error.h"
#include "cellmetry/exports/export_header.h"

namespace cellmetry {
namespace {

// The config's parameters must be the fitted values, bit for bit.
void CheckRebuilds(const CalibratedRobot& robot, const std::string& text,
                   const Registry& registry) {
  const ConfigNode config = ConfigNode::LoadString(text, "the exported robot config");
  const auto rebuilt = registry.CreateRobotModel(robot.model_type, config);
  const auto& parameters = rebuilt->parameters();
  bool same = parameters.size() == robot.values.size();
  for (size_t i = 0; same && i < parameters.size(); ++i) {
    same = parameters[i].nominal == robot.values[i];
  }
  if (!same) {
    throw std::logic_error("robot model " + robot.model_type +
                           "'s calibrated config does not "
                           "rebuild the fitted values");
  }
}

}  // namespace

std::string RobotConfigExport(const CalibratedCell& cell, const CalibratedRobot& robot,
                              const Registry& registry) {
  const std::string config =
      robot.model->CalibratedConfig(*robot.model_config, robot.values.data());
  if (config.empty()) {
    throw InputError({cell.json_path, 0, 0},
                     "robot model '" + robot.model_type + "' cannot write its config",
                     "Export the frames with --format tf");
  }
  CheckRebuilds(robot, config, registry);
  std::vector<std::string> lines = ExportHeader(cell, "robot", &robot);
  lines.push_back("");
  lines.push_back(
      "The calibrated robot as a robot config: give it as a job's `model:`. Its "
      "values are the fitted ones (every digit); the base and tools are the job's, "
      "not the robot's (result.yaml has them).");
  if (!robot.fitted.empty()) {
    lines.push_back(
        "Fitted here (sigma from the run; the values below are the nominal ones of a "
        "next job, which holds them unless it frees them):");
    for (const auto& p : robot.fitted) lines.push_back("  " + p.name + " = " + ValueWithSigma(p));
  }
  const std::vector<std::string> left_out = LeftOut(cell, robot, {});
  if (!left_out.empty()) {
    lines.push_back(
        "Not in this config (a robot config holds geometry only; put them under the "
        "job's `effects:`):");
    for (const auto& line : left_out) lines.push_back("  " + line);
  }
  return CommentLines(lines, "# ") + config;
}

}  // namespace cellmetry
