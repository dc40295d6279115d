// A simulation's truth and scoring a result against it.
//
// truth.yaml:  format: cellmetry-truth/1
//              frames: {<name>: {parent, xyz, rvec}}      # same names as result.yaml
//              model:  {<robot>.model.<param>: value}
//
// EvaluateWorkcell (evaluation.cc) takes a result.json as ReadWorkcellResult reads it
// (formats/workcell_result_file.h) and gives each estimate's error in its unit and in its own
// sigma; where parameters were in a gauge, the error of the combination the data determined.
#pragma once

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/workcell_result_file.h"

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
  std::string name;  // "ur3.base.x", "ur3.base.rot_x", "ur3.model.j2.d"
  std::string unit;
  double error = 0.0;  // estimate - truth (rotations: log(R_est R_true^T), parent axes)
  double sigma = 0.0;
  // In a gauge with a parameter the data could not determine (held at nominal): its error
  // includes the held one's, and the combination below is what the data determined.
  bool in_gauge = false;
  // A combination the data determines, "partner - ratio held" (estimation_quality.h
  // UnidentifiableParameter::moves_with), named after its terms.
  bool combination = false;
  double normalized() const { return sigma > 0 ? error / sigma : (error == 0 ? 0.0 : INFINITY); }
};

struct WorkcellEvaluation {
  // Held entries (sigma 0) are skipped; gauge combinations follow the single quantities. The
  // maxima leave out quantities in a gauge and count their combinations.
  std::vector<EvaluatedQuantity> quantities;
  double max_translation_error_mm = 0.0;
  double max_rotation_error_rad = 0.0;
  double max_abs_normalized = 0.0;
};

// `result` is result.json read back (ReadWorkcellResult); frames and model parameters absent
// from the truth are an InputError naming `truth_origin`.
WorkcellEvaluation EvaluateWorkcell(const WorkcellResultFile& result, const WorkcellTruth& truth,
                                    const std::string& truth_origin);
// The same for a result held in memory as WorkcellResultJson (result_io.h) gives it.
WorkcellEvaluation EvaluateWorkcell(const nlohmann::json& result, const WorkcellTruth& truth,
                                    const std::string& truth_origin);

}  // namespace cellmetry
