// A simulation's truth and scoring a result against it.
//
// truth.yaml:  format: cellmetry-truth/1
//              frames: {<name>: {parent, xyz, rvec}}      # same names as result.yaml
//              model:  {<robot>.model.<param>: value}
//
// EvaluateWorkcell reads a result.json (result_io.h) and gives each estimate's error in its unit
// and in its own sigma.
#pragma once

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

struct FrameTruth {
  std::string parent;
  Pose pose;
};

struct WorkcellTruth {
  std::map<std::string, FrameTruth> frames;
  std::map<std::string, double> model;
};

std::string TruthYaml(const WorkcellTruth& truth);
WorkcellTruth ReadTruth(const std::string& path);

// Error of each estimate against the truth, in units and in its own sigma.
struct EvaluatedQuantity {
  std::string name;         // "ur3.base.x", "ur3.base.rot_x", "ur3.model.j2.d"
  std::string unit;
  double error = 0.0;       // estimate - truth (rotations: log(R_est R_true^T), parent axes)
  double sigma = 0.0;
  double normalized() const { return sigma > 0 ? error / sigma : (error == 0 ? 0.0 : INFINITY); }
};

struct WorkcellEvaluation {
  std::vector<EvaluatedQuantity> quantities;  // held entries (sigma 0) are skipped
  double max_translation_error_mm = 0.0;
  double max_rotation_error_rad = 0.0;
  double max_abs_normalized = 0.0;
};

// `result` is result.json (result_io.h); frames and model parameters absent from the truth are
// an InputError naming `truth_origin`.
WorkcellEvaluation EvaluateWorkcell(const nlohmann::json& result, const WorkcellTruth& truth,
                                    const std::string& truth_origin);

}  // namespace cellmetry
