// Predicting where a carried target is, and how well any estimator could predict it.
//
//   PredictInCamera       the target's position in a camera for command q, at an estimate
//   ComparePredictions    distance between two estimates' predictions over commands (an answer
//                         against the truth on fresh positions: the 2023 report's Table 7)
//   PredictionErrorFloorMm  the Cramer-Rao floor of that distance's RMS for a design
#pragma once

#include <string>
#include <vector>

#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/estimation/estimation_quality.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

// Which robot, target and camera a prediction is about.
struct PredictedTarget {
  std::string robot;
  std::string target;
  std::string camera;
};

// false where the model has no pose for q.
bool PredictInCamera(const RobotModel& model, const WorkcellEstimate& estimate,
                     const PredictedTarget& what, const std::vector<double>& q,
                     Eigen::Vector3d* p_cam_mm);

struct PredictionError {
  double mean_mm = 0.0;
  double max_mm = 0.0;
  double rms_mm = 0.0;
  int points = 0;
};
PredictionError ComparePredictions(const RobotModel& model, const WorkcellEstimate& estimate,
                                   const WorkcellEstimate& truth, const PredictedTarget& what,
                                   const std::vector<std::vector<double>>& commands);

// The best any unbiased estimator can do on this design (Cramer-Rao): the RMS, over the
// `validation` commands, of the prediction error in the camera frame,
//   floor^2 = mean_v trace(G_v F^-1 G_v^T),   F = J^T J   (J whitened by the problem's sigma),
// with J the design's Jacobian (Cartesian residuals) and G_v the prediction's Jacobian, both at
// `truth` and over the free parameters that remain once `held` are held. docs/delta.md derives
// it.
double PredictionErrorFloorMm(const WorkcellProblem& problem, const Recording& design,
                              const PredictedTarget& what,
                              const std::vector<std::vector<double>>& validation,
                              const WorkcellEstimate& truth,
                              const std::vector<UnidentifiableParameter>& held);

}  // namespace cellmetry
