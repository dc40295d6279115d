// Where residuals follow something (internal to the core): the regressors a recording offers,
// per residual row of the carried targets' positions, and their partial correlation with the
// residuals after removing what the current model explains.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/diagnosis/diagnosis.h"
#include "diagnosis_linear.h"

namespace cellmetry {

struct Regressor {
  std::string name;                // "joint 2 gravity torque"
  std::vector<double> per_sample;  // by sample index; NaN where unknown
};

// Joint angles, gravity torques (lumped masses), approach directions, capture order, time,
// temperature, payload: those that vary in the recording; a step in capture order after every
// tenth of the run (something that moved once); and, where the samples' times show a pause (at
// least a minute and ten times the median interval), a step across the longest.
std::vector<Regressor> SampleRegressors(const Recording& recording,
                                        const std::vector<SampleFacts>& facts,
                                        const std::vector<double>& link_masses_kg,
                                        const Eigen::Vector3d& gravity_base);

// Partial correlations of the position residuals of carried targets, per camera axis, with every
// sample regressor and with the measured depth and image position, over all cameras and over
// each camera alone; most significant first (p-values Bonferroni-corrected over all of them).
std::vector<RegressorFinding> CorrelateRegressors(const CandidateLinearization& lin,
                                                  const Recording& recording,
                                                  const std::vector<Regressor>& regressors);

// Durbin-Watson per camera axis of the carried targets' position residuals in capture order.
std::map<std::string, double> DurbinWatsonByAxis(const CandidateLinearization& lin,
                                                 const Recording& recording);

}  // namespace cellmetry
