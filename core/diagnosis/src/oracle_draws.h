// The oracle's draws on the first-order model (internal to the core; oracle_selection.h has the
// model and why): given each candidate's unabsorbed basis and the mismatch d, the histograms of
// the Bayes choice's top posterior, split by whether the choice is right.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "cellmetry/diagnosis/oracle_selection.h"

namespace cellmetry {

struct OracleChoice {
  Eigen::MatrixXd U;   // orthonormal basis of what the geometry leaves of its columns
  bool right = false;  // names the expected physics
};

// Fills `out`'s histograms (`options.posterior_bins` each) from `options.draws` draws of
// r = d + e, e ~ N(0, I) in the span of the bases (what lies outside it changes no statistic).
void DrawBayesChoices(const std::vector<OracleChoice>& choices, const Eigen::VectorXd& d,
                      const OracleSelectionOptions& options, OracleSelection* out);

}  // namespace cellmetry
