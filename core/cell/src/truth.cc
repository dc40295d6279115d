// truth.yaml and scoring a result against it (truth.h).
#include "cellmetry/cell/truth.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>

#include "cellmetry/basics/error.h"
#include "cellmetry/formats/config_fields.h"
#include "cellmetry/formats/config_node.h"

namespace cellmetry {

std::string TruthYaml(const WorkcellTruth& truth) {
  YAML::Emitter out;
  out << YAML::Comment("simulation truth: never read by a calibration; lengths mm, angles rad");
  out << YAML::BeginMap << YAML::Key << "format" << YAML::Value << "cellmetry-truth/1";
  out << YAML::Key << "frames" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, frame] : truth.frames) {
    const Eigen::Vector3d rvec = RvecFromRotation(frame.pose.R);
    out << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "parent" << YAML::Value << frame.parent;
    out << YAML::Key << "xyz" << YAML::Value
        << std::vector<double>{frame.pose.t.x(), frame.pose.t.y(), frame.pose.t.z()};
    out << YAML::Key << "rvec" << YAML::Value << std::vector<double>{rvec.x(), rvec.y(), rvec.z()};
    out << YAML::EndMap;
  }
  out << YAML::EndMap << YAML::Key << "model" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, value] : truth.model) out << YAML::Key << name << YAML::Value << value;
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

WorkcellTruth ReadTruth(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"format", "frames", "model"});
  if (root["format"].AsString() != "cellmetry-truth/1") {
    throw root["format"].Error("unsupported truth format", "Expected cellmetry-truth/1");
  }
  WorkcellTruth truth;
  const ConfigNode frames = root["frames"];
  for (const auto& name : frames.Keys()) {
    const ConfigNode frame = frames[name];
    frame.ExpectKeys({"parent", "xyz", "rvec"});
    truth.frames[name] = {frame["parent"].AsString(), ReadPose(frame)};
  }
  if (root.Has("model")) {
    const ConfigNode model = root["model"];
    for (const auto& name : model.Keys()) truth.model[name] = model[name].AsDouble();
  }
  return truth;
}

}  // namespace cellmetry
