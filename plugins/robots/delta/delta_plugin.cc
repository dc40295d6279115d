// Registers the `delta` robot model: reads the arm dimensions, marker offset, motor resolution
// and workspace from a robot config (configs/robots/delta.yaml).
#include <cmath>

#include "cellmetry/formats/units.h"
#include "cellmetry/registry/registry.h"
#include "delta_model.h"

namespace cellmetry::delta {
namespace {

double Positive(const ConfigNode& node, const std::string& key, double fallback, double scale) {
  const double value = node.GetDouble(key, fallback / scale) * scale;
  if (!(value > 0.0))
    throw node[key].Error("must be positive", "Give the length in the config's units");
  return value;
}

Arm ReadArm(const ConfigNode& node, const Units& u) {
  node.ExpectKeys({"R", "r", "L", "l", "homing"});
  Arm arm;
  arm.R = Positive(node, "R", arm.R, u.to_mm);
  arm.r = node.GetDouble("r", arm.r / u.to_mm) * u.to_mm;
  arm.L = Positive(node, "L", arm.L, u.to_mm);
  arm.l = Positive(node, "l", arm.l, u.to_mm);
  arm.homing = node.GetDouble("homing", 0.0) * u.to_rad;
  return arm;
}

RobotLimits ReadLimits(const ConfigNode& config, const Units& u) {
  RobotLimits limits;
  if (config.Has("motor")) {
    const ConfigNode motor = config["motor"];
    motor.ExpectKeys({"increments_per_revolution"});
    const int increments = motor["increments_per_revolution"].AsInt();
    if (increments < 1) {
      throw motor["increments_per_revolution"].Error("must be at least 1",
                                                     "Give the motor's steps x microsteps x gear");
    }
    limits.joint_increment_rad = 2.0 * M_PI / increments;
  }
  if (config.Has("joint_limits")) {
    const ConfigNode node = config["joint_limits"];
    node.ExpectKeys({"min", "max"});
    const double lo = node["min"].AsDouble() * u.to_rad, hi = node["max"].AsDouble() * u.to_rad;
    if (!(lo < hi)) throw node.Error("min must be below max");
    limits.joint_min_rad.assign(kArms, lo);
    limits.joint_max_rad.assign(kArms, hi);
  }
  if (config.Has("workspace")) {
    const ConfigNode node = config["workspace"];
    node.ExpectKeys({"radius", "z_min", "z_max"});
    CylinderWorkspace w;
    w.radius_mm = Positive(node, "radius", 1.0, u.to_mm);
    w.z_min_mm = node["z_min"].AsDouble() * u.to_mm;
    w.z_max_mm = node["z_max"].AsDouble() * u.to_mm;
    if (!(w.z_min_mm < w.z_max_mm)) throw node.Error("z_min must be below z_max");
    limits.workspace = w;
  }
  return limits;
}

std::unique_ptr<RobotModel> Create(const ConfigNode& config) {
  config.ExpectKeys({"type", "name", "description", "units", "arms", "marker_offset", "motor",
                     "joint_limits", "workspace"});
  const Units units = ReadOptionalUnits(config);
  std::array<Arm, kArms> arms;
  const std::vector<ConfigNode> nodes = config["arms"].Elements();
  if (nodes.size() != kArms) {
    throw config["arms"].Error("a delta arm has 3 arms, this lists " + std::to_string(nodes.size()),
                               "List {R, r, L, l, homing} for arm 1, 2 and 3");
  }
  for (int i = 0; i < kArms; ++i) arms[i] = ReadArm(nodes[i], units);
  Pose marker = Pose::Identity();
  if (config.Has("marker_offset")) {
    const ConfigNode node = config["marker_offset"];
    node.ExpectKeys({"xyz"});
    const auto xyz = node["xyz"].AsDoubles(3);
    marker.t = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]) * units.to_mm;
  }
  return std::make_unique<DeltaModel>(arms, marker, ReadLimits(config, units));
}

}  // namespace
}  // namespace cellmetry::delta

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.name = "delta";
  info.description =
      "rotary delta arm, exact three-sphere forward and closed-form inverse kinematics";
  info.options = {
      {"arms", "", "",
       "three {R, r, L, l mm, homing rad}: base radius, effector radius, upper arm, rod"},
      {"marker_offset", "mm", "{xyz: [0, 0, 0]}", "marker on the extender, in the effector frame"},
      {"motor", "", "", "{increments_per_revolution}: motor resolution, for homing in increments"},
      {"joint_limits", "rad", "", "{min, max} motor angle"},
      {"workspace", "mm", "", "{radius, z_min, z_max}: cylinder where the effector may go"},
      {"units", "", "{length: mm, angle: rad}", "units of the config (mm|m, rad|deg)"},
      {"name", "", "", "robot name for reports"},
  };
  registry->AddRobotModel(info, &cellmetry::delta::Create);
}
