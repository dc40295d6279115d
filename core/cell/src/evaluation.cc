// Scoring a result against a simulation's truth (truth.h): each estimate's error in its unit and
// in its own sigma, and, where the data left parameters in a gauge, the combinations it did
// determine.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/truth.h"

namespace cellmetry {
namespace {

const char* kAxes[3] = {"x", "y", "z"};

Eigen::Vector3d Vec(const nlohmann::json& j) {
  return Eigen::Vector3d(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
}

// A held entry's sigma is null: it was not estimated. Held entries keep sigma 0 here.
Eigen::Vector3d SigmaOrZero(const nlohmann::json& j) {
  Eigen::Vector3d s;
  for (int i = 0; i < 3; ++i) s[i] = j[i].is_null() ? 0.0 : j[i].get<double>();
  return s;
}

// Every error by the result's parameter name ("ur3.base.rz", "ur3.model.j1.offset"), held ones
// included (sigma 0), each with the name it is reported under ("ur3.base.rot_z").
using ErrorsByParameter = std::map<std::string, EvaluatedQuantity>;

void AddFrameErrors(const nlohmann::json& result, const WorkcellTruth& truth,
                    const std::string& truth_origin, std::vector<std::string>* order,
                    ErrorsByParameter* errors) {
  for (const auto& [name, frame] : result.at("frames").items()) {
    const auto it = truth.frames.find(name);
    if (it == truth.frames.end()) {
      throw InputError({truth_origin, 0, 0}, "the truth has no frame '" + name + "'",
                       "Evaluate a result against the truth of the same simulation");
    }
    const Eigen::Vector3d dt = Vec(frame.at("xyz_mm")) - it->second.pose.t;
    const Eigen::Vector3d rvec = Vec(frame.at("rvec_rad"));
    const Eigen::Vector3d dr = RotationError<double>(RotationFromRvec(rvec.data()),
                                                     it->second.pose.R);
    const Eigen::Vector3d st = SigmaOrZero(frame.at("sigma_xyz_mm"));
    const Eigen::Vector3d sr = SigmaOrZero(frame.at("sigma_rot_rad"));
    for (int i = 0; i < 3; ++i) {
      const std::string axis = kAxes[i];
      order->push_back(name + "." + axis);
      (*errors)[name + "." + axis] = {name + "." + axis, "mm", dt[i], st[i]};
      order->push_back(name + ".r" + axis);
      (*errors)[name + ".r" + axis] = {name + ".rot_" + axis, "rad", dr[i], sr[i]};
    }
  }
}

void AddModelErrors(const nlohmann::json& result, const WorkcellTruth& truth,
                    const std::string& truth_origin, std::vector<std::string>* order,
                    ErrorsByParameter* errors) {
  for (const auto& p : result.at("model_parameters")) {
    const std::string name = p.at("name");
    const auto it = truth.model.find(name);
    // A block the simulation has no truth for at all (a nuisance effect the job added, such as
    // a detection bias) is not scored; a missing entry of a simulated block is an error.
    const std::string block = name.substr(0, name.find('.', name.find('.') + 1) + 1);
    const bool block_simulated =
        std::any_of(truth.model.begin(), truth.model.end(),
                    [&](const auto& t) { return t.first.rfind(block, 0) == 0; });
    if (it == truth.model.end() && !block_simulated) continue;
    if (it == truth.model.end()) {
      throw InputError({truth_origin, 0, 0}, "the truth has no model parameter '" + name + "'",
                       "Evaluate a result against the truth of the same simulation");
    }
    const bool held = p.at("held").get<bool>();
    order->push_back(name);
    (*errors)[name] = {name, p.at("unit"), p.at("value").get<double>() - it->second,
                       held ? 0.0 : p.at("sigma").get<double>()};
  }
}

// Every robot in every other robot's base (robot_to_robot), against the truth's two bases.
void AddRobotPairErrors(const nlohmann::json& result, const WorkcellTruth& truth,
                        std::vector<EvaluatedQuantity>* quantities) {
  if (!result.contains("robot_to_robot")) return;
  for (const auto& [name, pair] : result.at("robot_to_robot").items()) {
    const auto a = truth.frames.find(pair.at("parent").get<std::string>());
    const auto b = truth.frames.find(pair.at("frame").get<std::string>());
    if (a == truth.frames.end() || b == truth.frames.end()) continue;  // bases scored above
    const Pose true_ab = a->second.pose.inverse() * b->second.pose;
    const Eigen::Vector3d dt = Vec(pair.at("xyz_mm")) - true_ab.t;
    const Eigen::Vector3d rvec = Vec(pair.at("rvec_rad"));
    const Eigen::Vector3d dr = RotationError<double>(RotationFromRvec(rvec.data()), true_ab.R);
    const Eigen::Vector3d st = Vec(pair.at("sigma_xyz_mm")), sr = Vec(pair.at("sigma_rot_rad"));
    for (int i = 0; i < 3; ++i) {
      if (st[i] > 0) quantities->push_back({name + "." + kAxes[i], "mm", dt[i], st[i]});
      if (sr[i] > 0) quantities->push_back({name + ".rot_" + kAxes[i], "rad", dr[i], sr[i]});
    }
  }
}

// "ur3.base.rot_z + 1.00 ur3.model.j1.offset": partner - ratio * held.
std::string CombinationName(const std::string& partner, double ratio, const std::string& held) {
  char coefficient[32];
  std::snprintf(coefficient, sizeof coefficient, "%.3g", std::abs(ratio));
  return partner + (ratio > 0 ? " - " : " + ") + coefficient + " " + held;
}

// A parameter held because the data cannot see a direction carries no error of its own; its
// error moved into its partners along that direction (estimation_quality.h). What the data
// determines is partner - ratio * held, whose sigma is the partner's (the held one is fixed).
// The partner's own row is then a gauge artefact: kept, but marked and left out of the maxima.
void AddGaugeCombinations(const nlohmann::json& result, const ErrorsByParameter& errors,
                          WorkcellEvaluation* evaluation) {
  if (!result.contains("unidentifiable")) return;
  for (const auto& held : result.at("unidentifiable")) {
    const auto a = errors.find(held.at("name").get<std::string>());
    if (a == errors.end() || !held.contains("moves_with")) continue;
    for (const auto& partner : held.at("moves_with")) {
      const auto b = errors.find(partner.at("name").get<std::string>());
      if (b == errors.end() || !(b->second.sigma > 0)) continue;
      const double ratio = partner.at("ratio").get<double>();
      for (auto& q : evaluation->quantities) {
        if (q.name == b->second.name) q.in_gauge = true;
      }
      EvaluatedQuantity combination{CombinationName(b->second.name, ratio, a->second.name),
                                    b->second.unit,
                                    b->second.error - ratio * a->second.error, b->second.sigma};
      combination.combination = true;
      evaluation->quantities.push_back(combination);
    }
  }
}

}  // namespace

WorkcellEvaluation EvaluateWorkcell(const nlohmann::json& result, const WorkcellTruth& truth,
                                    const std::string& truth_origin) {
  std::vector<std::string> order;
  ErrorsByParameter errors;
  AddFrameErrors(result, truth, truth_origin, &order, &errors);
  AddModelErrors(result, truth, truth_origin, &order, &errors);
  WorkcellEvaluation evaluation;
  for (const auto& name : order) {
    if (errors.at(name).sigma > 0) evaluation.quantities.push_back(errors.at(name));
  }
  AddRobotPairErrors(result, truth, &evaluation.quantities);
  AddGaugeCombinations(result, errors, &evaluation);
  for (const auto& q : evaluation.quantities) {
    if (q.in_gauge) continue;  // its combination is scored instead
    double& worst = q.unit == "rad" ? evaluation.max_rotation_error_rad
                                    : evaluation.max_translation_error_mm;
    if (!q.combination) worst = std::max(worst, std::abs(q.error));
    evaluation.max_abs_normalized = std::max(evaluation.max_abs_normalized,
                                             std::abs(q.normalized()));
  }
  return evaluation;
}

}  // namespace cellmetry
