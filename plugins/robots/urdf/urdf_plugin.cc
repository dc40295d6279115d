// Registers the `urdf` robot model: the revolute chain between two links of a URDF file,
// calibrated through its joint origins (urdf_model.h). Config: `file` (relative to the config),
// `base_link`, `tip_link`, all required; `calibrated:` ({<joint>.<parameter>: value}, what
// `cellmetry export --format robot` writes) replaces nominal values, a name the chain does not
// have refused with the nearest one.
#include "cellmetry/registry/registry.h"
#include "urdf_chain.h"
#include "urdf_model.h"

namespace cellmetry::urdf_robot {
namespace {

std::unique_ptr<RobotModel> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "name", "description", "file", "base_link", "tip_link", "calibrated"});
  for (const char* key : {"file", "base_link", "tip_link"}) {
    if (!config.Has(key)) {
      throw config.Error(std::string("a urdf robot needs `") + key + "`",
                         "Give file (the URDF, relative to this config), base_link and tip_link");
    }
  }
  auto model = std::make_unique<UrdfModel>(ReadUrdfChain(config));
  if (config.Has("calibrated")) {
    const ConfigNode values = config["calibrated"];
    for (const std::string& name : values.Keys()) {
      if (!model->SetNominal(name, values[name].AsDouble())) {
        std::vector<std::string> names;
        for (const Parameter& p : model->parameters()) names.push_back(p.name);
        const std::string nearest = NearestWord(name, names);
        throw values[name].Error(
            "no parameter '" + name + "' on the chain from " + config["base_link"].AsString() +
                " to " + config["tip_link"].AsString(),
            nearest.empty() ? "Name a parameter as <joint>.x|y|z|roll|pitch|yaw|offset"
                            : "Did you mean '" + nearest + "'?");
      }
    }
  }
  return model;
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
      {"calibrated", "mm, rad", "", "{<joint>.<parameter>: value}: replaces nominal values"},
      {"name", "", "", "robot name for reports"},
  };
  registry->AddRobotModel(info, &cellmetry::urdf_robot::Create);
}
