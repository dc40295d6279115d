// Writing kinematic calibration and homing results.
//
//   kinematic: result.yaml  camera pose, marker, model parameters (value, sigma), paste-ready
//              result.json  everything, plus the validation on fresh positions when given
//              residuals.csv one row per measured position: prediction - measurement, camera axes
//   homing:    homing.yaml  offsets (rad and increments) by both methods, positions, widths
// Each folder is written atomically (whole or not at all).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/cell/homing.h"
#include "cellmetry/cell/kinematic_calibration.h"

namespace cellmetry {

// Fresh positions the calibrated model was scored on (prediction - measurement).
struct KinematicValidation {
  std::string recording;
  ResidualRms before;   // with the nominal model and the closed-form camera
  ResidualRms after;    // with the calibrated model
  double mean_after_mm = 0.0;
  double max_after_mm = 0.0;
};

std::string KinematicResultYaml(const KinematicResult& result);
nlohmann::json KinematicResultJson(const KinematicResult& result,
                                   const std::optional<KinematicValidation>& validation);
std::string KinematicResidualsCsv(const KinematicProblem& problem, const KinematicResult& result,
                                  const std::vector<PointSample>& samples);
void WriteKinematicResult(const KinematicProblem& problem, const KinematicResult& result,
                          const std::vector<PointSample>& samples,
                          const std::optional<KinematicValidation>& validation,
                          const std::string& folder);
std::string KinematicSummary(const KinematicResult& result,
                             const std::optional<KinematicValidation>& validation);

std::string HomingYaml(const HomingResult& result);
void WriteHomingResult(const HomingResult& result, const std::string& folder);
std::string HomingSummary(const HomingResult& result);

}  // namespace cellmetry
