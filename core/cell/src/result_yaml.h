// YAML pieces shared by the result writers (internal to the core).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "cellmetry/cell/workcell_result.h"
#include "result_json.h"

namespace cellmetry {

// `name: {parent, xyz, rvec, sigma_xyz, sigma_rot}` (mm, rad).
inline void EmitFrameYaml(YAML::Emitter& out, const std::string& name, const FrameEstimate& f) {
  out << YAML::Key << name << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "parent" << YAML::Value << f.parent;
  out << YAML::Key << "xyz" << YAML::Value << YAML::Flow << Vec(f.pose.t);
  out << YAML::Key << "rvec" << YAML::Value << YAML::Flow << Vec(RvecFromRotation(f.pose.R));
  out << YAML::Key << "sigma_xyz" << YAML::Value << YAML::Flow << Vec(f.sigma_mm);
  out << YAML::Key << "sigma_rot" << YAML::Value << YAML::Flow << Vec(f.sigma_rad);
  out << YAML::EndMap;
}

}  // namespace cellmetry
