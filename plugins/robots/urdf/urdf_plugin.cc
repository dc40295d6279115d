// Registers the `urdf` robot model: the revolute chain between two links of a URDF file,
// calibrated through its joint origins (urdf_model.h).
#include "cellmetry/registry/registry.h"
#include "urdf_chain.h"
#include "urdf_model.h"

namespace cellmetry::urdf_robot {
namespace {

std::unique_ptr<RobotModel> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "name", "description", "file", "base_link", "tip_link"});
  for (const char* key : {"file", "base_link", "tip_link"}) {
    if (!config.Has(key)) {
      throw config.Error(std::string("a urdf robot needs `") + key + "`",
                         "Give file (the URDF, relative to this config), base_link and tip_link");
    }
  }
  return std::make_unique<UrdfModel>(ReadUrdfChain(config));
}

}  // namespace
}  // namespace cellmetry::urdf_robot

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.name = "urdf";
  info.description =
      "serial arm from a URDF chain between two links, calibrated through its joint origins";
  info.options = {
      {"file", "", "", "the URDF (expanded xacro), relative to this config"},
      {"base_link", "", "", "the link the base frame is"},
      {"tip_link", "", "", "the link the flange frame is"},
      {"name", "", "", "robot name for reports"},
  };
  registry->AddRobotModel(info, &cellmetry::urdf_robot::Create);
}
