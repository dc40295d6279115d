// Registers the `serial_mdh` robot model: reads the MDH table from a robot config.
#include <cmath>

#include "cellmetry/registry/registry.h"
#include "cellmetry/formats/units.h"
#include "serial_mdh_model.h"

namespace cellmetry::serial_mdh {
namespace {

std::unique_ptr<RobotModel> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "name", "description", "units", "joints"});
  const Units units = ReadOptionalUnits(config);
  const double to_mm = units.to_mm, to_rad = units.to_rad;
  std::vector<Joint> joints;
  for (const auto& node : config["joints"].Elements()) {
    node.ExpectKeys({"alpha", "a", "beta", "d", "offset"});
    // The table's four entries are required, 0 written out: a forgotten `d` read as 0 moves the
    // whole arm without a word. beta (Hayati's angle) and offset default to 0.
    Joint joint;
    joint.alpha = node["alpha"].AsDouble() * to_rad;
    joint.a = node["a"].AsDouble() * to_mm;
    joint.beta = node.GetDouble("beta", 0.0) * to_rad;
    joint.d = node["d"].AsDouble() * to_mm;
    joint.offset = node.GetDouble("offset", 0.0) * to_rad;
    joints.push_back(joint);
  }
  if (joints.empty()) throw config["joints"].Error("no joints", "List one entry per joint");
  return std::make_unique<SerialMdhModel>(std::move(joints));
}

}  // namespace
}  // namespace cellmetry::serial_mdh

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.name = "serial_mdh";
  info.description = "serial arm in modified DH (Craig), any number of joints, Hayati beta";
  info.options = {
      {"joints", "", "", "list of {alpha rad, a mm, beta rad, d mm, offset rad} per joint"},
      {"units", "", "{length: mm, angle: rad}", "units of the table (mm|m, rad|deg)"},
      {"name", "", "", "robot name for reports"},
  };
  registry->AddRobotModel(info, &cellmetry::serial_mdh::Create);
}
