// Reading the robot config a job or simulation names (robot_config.h).
#include "robot_config.h"

#include <filesystem>

#include "cellmetry/formats/input_file.h"

namespace cellmetry {

RobotConfig ReadRobotConfig(const ConfigNode& robot, const Registry& registry) {
  RobotConfig config;
  config.file = robot.ResolvePath(robot["model"].AsString());
  std::error_code unreadable;  // a name too long for the file system is "not found", not a throw
  if (!std::filesystem::exists(config.file, unreadable)) {
    throw robot["model"].Error("robot config '" + config.file + "' not found",
                               "Give a path relative to the job file");
  }
  const ConfigNode node = ConfigNode::LoadFile(config.file);
  config.text = ReadRegularFile(config.file, kMaxYamlBytes, "");  // just read as YAML: there
  config.type = node["type"].AsString();
  config.model = registry.CreateRobotModel(config.type, node);
  return config;
}

}  // namespace cellmetry
