// How often the poses let the right physics be the most probable candidate: an oracle's choice.
//
// The physics finder (diagnosis.h) names an effect only when its tests agree. Where the poses
// leave two candidates' signatures alike, no rule names the right one every time, and some of
// the finder's misses are the data's, not the finder's. This measures how open a case is. An
// oracle that knows the noise-free mismatch's size, the noise's sigma, and that exactly one of
// the candidates is behind it picks by Bayes' rule on the first-order model of the finder's
// first round (its score test's model, diagnosis_linear.h):
//
//   r = d + e,          e ~ N(0, I) whitened, outside the span of the geometry's columns,
//   candidate c:        r = U_c a + e,   a ~ N(0, tau_c^2 I),   tau_c^2 = |d|^2 / k_c,
//   log p(r | c)      = -k_c/2 ln(1 + tau_c^2) + tau_c^2 / (2 (1 + tau_c^2)) |U_c^T r|^2,
//
// with equal prior odds over the testable candidates. d is what the geometry, fitted to every
// observation, leaves of the noise-free mismatch, U_c an orthonormal basis of what it leaves of
// candidate c's columns (k_c of them). Under that prior the posterior's top candidate is the rule
// that is right most often (the maximum a posteriori choice); on one fixed case a rule leaning
// towards that case's answer could do better there, and worse on the others, so the share is a
// measure of the case, not a bound on a finder. The histograms by the top posterior also give,
// under the same prior, the best trade of right names for fewer wrong ones (name only above a
// posterior t: Chow 1970, "On optimum recognition error and reject tradeoff", IEEE Trans. Inf.
// Theory 16(1)).
//
// The draws need no refit: the statistics |U_c^T r|^2 depend on e only through z = G^T e with
// G = [U_1 ... U_C], which is N(0, G^T G) and drawn from its eigen-decomposition.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/diagnosis/diagnosis.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

struct OracleSelectionOptions {
  int draws = 4000;          // noise draws; the shares' standard error is below 0.008
  unsigned seed = 7;         // of the draws
  int posterior_bins = 100;  // the histograms' bins over the top posterior, [0, 1]
};

struct OracleSelection {
  double mismatch_norm = 0.0;  // |d|, whitened: the SNR of the mismatch's unabsorbed part
  int testable = 0;            // candidates the oracle chooses from
  int right_candidates = 0;    // of those, the ones that name the expected physics
  // Draws by the top candidate's posterior (bin b holds [b, b + 1) / bins; 1 in the last),
  // split by whether the top candidate names the expected physics.
  std::vector<int> right_by_posterior;
  std::vector<int> wrong_by_posterior;
  int draws() const;
  double right_share() const;  // draws whose top candidate is right (always naming it)
};

// `spec` is the diagnosis job's problem with its noise set to the recording's known sigma;
// `noise_free` the recording without noise (its mismatch alone); `expect` the case's answer as
// the physics suite scores it (a candidate's name or its prefix, or a group). A candidate is
// right when its name starts with `expect`, its group is `expect`, or its unabsorbed signature
// correlates at least `options.alias_correlation` with one that is (an exact alias, which the
// finder names together). Untestable candidates are left out as the finder leaves them out.
// When no testable candidate is right the case cannot be scored: no draws are made.
OracleSelection DrawOracleSelections(const WorkcellProblem& spec, const Recording& noise_free,
                                     const SolverMaker& make_solver,
                                     const std::vector<CandidateEffect>& candidates,
                                     const std::string& expect, const DiagnosisOptions& options,
                                     const OracleSelectionOptions& oracle);

}  // namespace cellmetry
