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

WorkcellEvaluation EvaluateWorkcell(const nlohmann::json& result, const WorkcellTruth& truth,
                                    const std::string& truth_origin) {
  WorkcellEvaluation evaluation;
  auto vec = [](const nlohmann::json& j) {
    return Eigen::Vector3d(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  };
  static const char* kAxes[3] = {"x", "y", "z"};
  for (const auto& [name, frame] : result.at("frames").items()) {
    const auto it = truth.frames.find(name);
    if (it == truth.frames.end()) {
      throw InputError({truth_origin, 0, 0}, "the truth has no frame '" + name + "'",
                       "Evaluate a result against the truth of the same simulation");
    }
    const Eigen::Vector3d t = vec(frame.at("xyz_mm")), rvec = vec(frame.at("rvec_rad"));
    const Eigen::Vector3d dt = t - it->second.pose.t;
    const Eigen::Vector3d dr = RotationError<double>(RotationFromRvec(rvec.data()),
                                                     it->second.pose.R);
    // A held entry's sigma is null: it was not estimated, so it is not scored.
    auto sigma = [](const nlohmann::json& j) {
      Eigen::Vector3d s;
      for (int i = 0; i < 3; ++i) s[i] = j[i].is_null() ? 0.0 : j[i].get<double>();
      return s;
    };
    const Eigen::Vector3d st = sigma(frame.at("sigma_xyz_mm"));
    const Eigen::Vector3d sr = sigma(frame.at("sigma_rot_rad"));
    for (int i = 0; i < 3; ++i) {
      if (st[i] > 0) {
        evaluation.quantities.push_back({name + "." + kAxes[i], "mm", dt[i], st[i]});
        evaluation.max_translation_error_mm =
            std::max(evaluation.max_translation_error_mm, std::abs(dt[i]));
      }
      if (sr[i] > 0) {
        evaluation.quantities.push_back({name + ".rot_" + kAxes[i], "rad", dr[i], sr[i]});
        evaluation.max_rotation_error_rad =
            std::max(evaluation.max_rotation_error_rad, std::abs(dr[i]));
      }
    }
  }
  // Every robot in every other robot's base (robot_to_robot), against the truth's two bases.
  if (result.contains("robot_to_robot")) {
    for (const auto& [name, pair] : result.at("robot_to_robot").items()) {
      const auto a = truth.frames.find(pair.at("parent").get<std::string>());
      const auto b = truth.frames.find(pair.at("frame").get<std::string>());
      if (a == truth.frames.end() || b == truth.frames.end()) continue;  // bases scored above
      const Pose true_ab = a->second.pose.inverse() * b->second.pose;
      const Eigen::Vector3d t = vec(pair.at("xyz_mm")), rvec = vec(pair.at("rvec_rad"));
      const Eigen::Vector3d dt = t - true_ab.t;
      const Eigen::Vector3d dr = RotationError<double>(RotationFromRvec(rvec.data()), true_ab.R);
      const Eigen::Vector3d st = vec(pair.at("sigma_xyz_mm")), sr = vec(pair.at("sigma_rot_rad"));
      for (int i = 0; i < 3; ++i) {
        if (st[i] > 0) evaluation.quantities.push_back({name + "." + kAxes[i], "mm", dt[i], st[i]});
        if (sr[i] > 0) {
          evaluation.quantities.push_back({name + ".rot_" + kAxes[i], "rad", dr[i], sr[i]});
        }
      }
    }
  }
  for (const auto& p : result.at("model_parameters")) {
    if (p.at("held").get<bool>()) continue;
    const std::string name = p.at("name");
    const auto it = truth.model.find(name);
    // A block the simulation has no truth for at all (a nuisance effect the job added, such as
    // a detection bias) is not scored; a missing entry of a simulated block is an error.
    const std::string block = name.substr(0, name.find('.', name.find('.') + 1) + 1);
    const bool block_simulated = std::any_of(truth.model.begin(), truth.model.end(), [&](const auto& t) {
      return t.first.rfind(block, 0) == 0;
    });
    if (it == truth.model.end() && !block_simulated) continue;
    if (it == truth.model.end()) {
      throw InputError({truth_origin, 0, 0}, "the truth has no model parameter '" + name + "'",
                       "Evaluate a result against the truth of the same simulation");
    }
    const std::string unit = p.at("unit");
    const double error = p.at("value").get<double>() - it->second;
    evaluation.quantities.push_back({name, unit, error, p.at("sigma").get<double>()});
    double& worst = unit == "rad" ? evaluation.max_rotation_error_rad
                                  : evaluation.max_translation_error_mm;
    worst = std::max(worst, std::abs(error));
  }
  for (const auto& q : evaluation.quantities) {
    evaluation.max_abs_normalized = std::max(evaluation.max_abs_normalized, std::abs(q.normalized()));
  }
  return evaluation;
}

}  // namespace cellmetry
