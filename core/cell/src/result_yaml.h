// YAML pieces shared by the result writers (internal to the core).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "cellmetry/cell/workcell_result.h"
#include "result_json.h"

namespace cellmetry {

// A sigma list with "held" where the entry was held (never 0, which reads as known perfectly).
inline void EmitSigmaYaml(YAML::Emitter& out, const Eigen::Vector3d& sigma,
                          const std::array<bool, 6>& held, int offset) {
  out << YAML::Flow << YAML::BeginSeq;
  for (int i = 0; i < 3; ++i) {
    if (held[offset + i]) {
      out << "held";
    } else {
      out << sigma[i];
    }
  }
  out << YAML::EndSeq;
}

// `name: {parent, xyz, rvec, sigma_xyz, sigma_rot}` (mm, rad).
inline void EmitFrameYaml(YAML::Emitter& out, const std::string& name, const FrameEstimate& f) {
  out << YAML::Key << name << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "parent" << YAML::Value << f.parent;
  out << YAML::Key << "xyz" << YAML::Value << YAML::Flow << Vec(f.pose.t);
  out << YAML::Key << "rvec" << YAML::Value << YAML::Flow << Vec(RvecFromRotation(f.pose.R));
  out << YAML::Key << "sigma_xyz" << YAML::Value;
  EmitSigmaYaml(out, f.sigma_mm, f.held, 0);
  out << YAML::Key << "sigma_rot" << YAML::Value;
  EmitSigmaYaml(out, f.sigma_rad, f.held, 3);
  out << YAML::EndMap;
}

}  // namespace cellmetry
