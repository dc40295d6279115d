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
#include "cellmetry/formats/workcell_result_file.h"

namespace cellmetry {
namespace {

const char* kAxes[3] = {"x", "y", "z"};

// A frame's sigma, translation (offset 0) or rotation (offset 3): a held entry has none, and
// keeps sigma 0 here.
Eigen::Vector3d SigmaOrZero(const CalibratedFrame& frame, int offset) {
  Eigen::Vector3d s;
  for (int i = 0; i < 3; ++i) s[i] = frame.sigma[offset + i].value_or(0.0);
  return s;
}

// Every error by the result's parameter name ("ur3.base.rz", "ur3.model.j1.offset"), held ones
// included (sigma 0), each with the name it is reported under ("ur3.base.rot_z").
using ErrorsByParameter = std::map<std::string, EvaluatedQuantity>;

void AddFrameErrors(const WorkcellResultFile& result, const WorkcellTruth& truth,
                    const std::string& truth_origin, std::vector<std::string>* order,
                    ErrorsByParameter* errors) {
  for (const CalibratedFrame& frame : result.frames) {
    const std::string& name = frame.name;
    const auto it = truth.frames.find(name);
    if (it == truth.frames.end()) {
      throw InputError({truth_origin, 0, 0}, "the truth has no frame '" + name + "'",
                       "Evaluate a result against the truth of the same simulation");
    }
    const Eigen::Vector3d dt = frame.T_parent_frame.t - it->second.pose.t;
    const Eigen::Vector3d dr = RotationError<double>(frame.T_parent_frame.R, it->second.pose.R);
    const Eigen::Vector3d st = SigmaOrZero(frame, 0);
    const Eigen::Vector3d sr = SigmaOrZero(frame, 3);
    for (int i = 0; i < 3; ++i) {
      const std::string axis = kAxes[i];
      order->push_back(name + "." + axis);
      (*errors)[name + "." + axis] = {name + "." + axis, "mm", dt[i], st[i]};
      order->push_back(name + ".r" + axis);
      (*errors)[name + ".r" + axis] = {name + ".rot_" + axis, "rad", dr[i], sr[i]};
    }
  }
}

void AddModelErrors(const WorkcellResultFile& result, const WorkcellTruth& truth,
                    const std::string& truth_origin, std::vector<std::string>* order,
                    ErrorsByParameter* errors) {
  for (const FittedScalar& p : result.model_parameters) {
    const std::string& name = p.name;
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
    order->push_back(name);
    (*errors)[name] = {name, p.unit, p.value - it->second, p.held ? 0.0 : p.sigma.value_or(0.0)};
  }
}

// Every robot in every other robot's base (robot_to_robot), against the truth's two bases.
void AddRobotPairErrors(const WorkcellResultFile& result, const WorkcellTruth& truth,
                        std::vector<EvaluatedQuantity>* quantities) {
  for (const ResultRobotPair& pair : result.robot_to_robot) {
    const std::string& name = pair.key;
    const auto a = truth.frames.find(pair.frame.parent);
    const auto b = truth.frames.find(pair.frame.name);
    if (a == truth.frames.end() || b == truth.frames.end()) continue;  // bases scored above
    const Pose true_ab = a->second.pose.inverse() * b->second.pose;
    const Eigen::Vector3d dt = pair.frame.T_parent_frame.t - true_ab.t;
    const Eigen::Vector3d dr = RotationError<double>(pair.frame.T_parent_frame.R, true_ab.R);
    const Eigen::Vector3d st = SigmaOrZero(pair.frame, 0), sr = SigmaOrZero(pair.frame, 3);
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
void AddGaugeCombinations(const WorkcellResultFile& result, const ErrorsByParameter& errors,
                          WorkcellEvaluation* evaluation) {
  for (const ResultUnidentifiable& held : result.unidentifiable) {
    const auto a = errors.find(held.name);
    if (a == errors.end()) continue;
    for (const ResultUnidentifiable::Partner& partner : held.moves_with) {
      const auto b = errors.find(partner.name);
      if (b == errors.end() || !(b->second.sigma > 0)) continue;
      const double ratio = partner.ratio;
      for (auto& q : evaluation->quantities) {
        if (q.name == b->second.name) q.in_gauge = true;
      }
      EvaluatedQuantity combination{CombinationName(b->second.name, ratio, a->second.name),
                                    b->second.unit, b->second.error - ratio * a->second.error,
                                    b->second.sigma};
      combination.combination = true;
      evaluation->quantities.push_back(combination);
    }
  }
}

}  // namespace

WorkcellEvaluation EvaluateWorkcell(const WorkcellResultFile& result, const WorkcellTruth& truth,
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
    double& worst =
        q.unit == "rad" ? evaluation.max_rotation_error_rad : evaluation.max_translation_error_mm;
    if (!q.combination) worst = std::max(worst, std::abs(q.error));
    evaluation.max_abs_normalized =
        std::max(evaluation.max_abs_normalized, std::abs(q.normalized()));
  }
  return evaluation;
}

WorkcellEvaluation EvaluateWorkcell(const nlohmann::json& result, const WorkcellTruth& truth,
                                    const std::string& truth_origin) {
  return EvaluateWorkcell(ParseWorkcellResult(result.dump(), "result.json"), truth, truth_origin);
}

}  // namespace cellmetry
