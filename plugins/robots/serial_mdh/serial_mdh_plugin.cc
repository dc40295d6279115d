// Registers the `serial_mdh` robot model: reads the MDH table from a robot config.
#include <cmath>

#include "cellmetry/formats/units.h"
#include "cellmetry/registry/registry.h"
#include "serial_mdh_model.h"

namespace cellmetry::serial_mdh {
namespace {

// 1 km: above any arm, and above a table of millimetres declared as metres (a UR3's 151.9 m),
// which the length-scale check explains better than a range can.
constexpr double kMaxLengthMm = 1e6;
constexpr double kMaxAngleRad = 100;  // sixteen turns, as a recording's joint readings

// `key` of a joint's row in mm or rad, refused at its value beyond any arm: a d of 1e300 was
// blamed on the units line as a size mismatch "by about inf times"; an offset of 1e9 rad ran.
// Optional entries default to 0.
double Entry(const ConfigNode& joint, const std::string& key, double to_unit, double max_abs,
             const char* unit, bool required) {
  if (!required && !joint.Has(key)) return 0.0;
  const double value = joint[key].AsDouble() * to_unit;
  if (std::abs(value) > max_abs) {
    throw joint[key].Error(
        "beyond any arm (|" + key + "| <= " + std::to_string(int(max_abs)) + " " + unit + ")",
        "Check the value and the units the config declares");
  }
  return value;
}

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
    joint.alpha = Entry(node, "alpha", to_rad, kMaxAngleRad, "rad", true);
    joint.a = Entry(node, "a", to_mm, kMaxLengthMm, "mm", true);
    joint.beta = Entry(node, "beta", to_rad, kMaxAngleRad, "rad", false);
    joint.d = Entry(node, "d", to_mm, kMaxLengthMm, "mm", true);
    joint.offset = Entry(node, "offset", to_rad, kMaxAngleRad, "rad", false);
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
