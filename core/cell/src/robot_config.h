// A robot's model from the robot config its job or simulation names (`model: <file>` in the
// robot's block), built through the registry: the one reader `cellmetry run` and `cellmetry
// simulate` share.
//
// Contract:
//  - The path is resolved against the folder of the file that names it.
//  - A config that is not there is an InputError at the `model:` value (file:line:column) that
//    names the path looked for; a name too long for the file system counts as not there.
//  - A config that does not read as YAML, has no `type:`, or names a type no plugin builds is
//    the InputError of the config file itself or of the registry.
#pragma once

#include <memory>
#include <string>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/model/robot_model.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

struct RobotConfig {
  std::string file;  // the config's path, resolved
  std::string text;  // the file's whole text: what a result records to rebuild the model
  std::string type;  // its `type:`, the robot-model plugin that built `model`
  std::shared_ptr<const RobotModel> model;
};

// The config `robot["model"]` names, and the model it describes at its nominal values.
RobotConfig ReadRobotConfig(const ConfigNode& robot, const Registry& registry);

}  // namespace cellmetry
