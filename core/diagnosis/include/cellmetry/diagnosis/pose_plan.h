// PlanPoses: the joint poses to record next, so that what the finder called untestable becomes
// testable and the free parameters are best determined (`cellmetry plan JOB.yaml`).
//
// Where `diagnose` says an effect is untestable here ("98 % of its signature is absorbed by the
// geometry; needs poses that load joint 2 differently"), the poses recorded so far cannot tell
// it from the geometry. The planner draws random joint poses inside the joint limits, keeps those
// whose target every camera that saw it before would see again (in front of it, within the
// depths and the angles off its axis it has seen), and chooses among them greedily by
// D-optimality (Fedorov 1972; Atkinson, Donev & Tobias 2007, ch. 9 and 12): each next pose is
// the one that most increases log det of the Fisher information of the free parameters and the
// named candidates' parameters together, given everything recorded and chosen so far,
//
//   gain(k) = log det(I + J_k M^-1 J_k^T),   M = sum of J_i^T J_i over recorded and chosen poses,
//
// J_k the whitened Jacobian rows of pose k at the fitted answer (the determinant lemma: no
// refactorization per candidate). A candidate whose signature the geometry absorbs leaves M
// nearly singular along it, so its direction dominates the gain until it is determined: the
// criterion makes it testable first and then spends the rest on the geometry. Predicted: the
// share of each candidate's signature outside the geometry's span, each of its parameters' sigma
// at the floor fitted together with the geometry (what the finder's refit would give, before the
// dispersion), and each free parameter's sigma at the floor, before and after.
//
// Named candidates need not be untestable: two that the finder's bootstrap could not tell apart
// (its report proposes the pair) are planned for together, the criterion then favouring the poses
// where their signatures differ; the plan adds how alike the poses leave them and their
// parameters' sigma fitted together (PlannedPair).
#pragma once

#include <string>
#include <vector>

#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/diagnosis/diagnosis.h"

namespace cellmetry {

struct PosePlanOptions {
  int poses = 10;    // how many to propose
  int draws = 2000;  // random joint poses to choose among
  unsigned seed = 1;
  double min_unabsorbed = 0.05;      // below: untestable (the finder's threshold)
  std::vector<std::string> effects;  // candidates to make testable; empty: every one the
                                     // recorded poses leave untestable by absorption
};

struct PlannedPose {
  std::string robot;
  std::vector<double> q;             // rad
  std::vector<std::string> cameras;  // that will see its target
};

struct PlannedSigma {
  std::string name, unit;
  double before = 0.0, after = 0.0;  // predicted sigma at the floor
};

struct PlannedEffect {
  std::string name, label;
  double unabsorbed_before = 0.0;  // share of its signature outside the geometry's span
  double unabsorbed_after = 0.0;
  std::vector<PlannedSigma> sigma;  // its parameters, fitted with the geometry
};

// Two named candidates planned for together (PosePlanOptions::effects, the diagnose report's
// closest candidate and its bootstrap rival): how alike the poses leave them, as the finder
// measures it (the largest canonical correlation of what the geometry leaves of their
// signatures; at `alias_correlation`, 0.99, the finder calls them one finding).
struct PlannedPair {
  std::string a, b;  // labels
  double correlation_before = 0.0, correlation_after = 0.0;
  std::vector<PlannedSigma> sigma;  // both one's and the other's parameters, fitted together
                                    // with the geometry: how well the data would separate them
};

struct PosePlan {
  std::vector<PlannedPose> poses;
  std::vector<PlannedEffect> effects;
  std::vector<PlannedPair> pairs;  // every two named candidates (none when none are named)
  std::vector<PlannedSigma> sigma;
  int draws = 0;                 // options.draws: poses drawn inside the joint limits
  int draws_in_view = 0;         // of those, the ones some camera would see
  double min_unabsorbed = 0.05;  // options.min_unabsorbed: testable from here
};

// Whether the plan reached what it was asked: every planned effect testable after it, and every
// named pair less alike than before and below the finder's 0.99. `unmet` says, one line each,
// what it did not reach.
bool PlanMeetsItsGoal(const PosePlan& plan, std::vector<std::string>* unmet);

// Raises InputError (at --effect) for a name in options.effects that no candidate has, listing
// the names there are. PlanPoses checks it too; a caller checks it before the identification
// PlanPoses needs, so that a misspelt name is refused before that work, not after it.
void CheckNamedEffects(const std::vector<CandidateEffect>& candidates,
                       const PosePlanOptions& options);

// `fitted` is the job's identification on `recording` (its estimate and noise model);
// `candidates` the finder's (DefaultCandidates or the job's). Raises InputError when no drawn
// pose would be seen by a camera, and as CheckNamedEffects.
PosePlan PlanPoses(const WorkcellProblem& spec, const Recording& recording,
                   const WorkcellResult& fitted, const std::vector<CandidateEffect>& candidates,
                   const PosePlanOptions& options);

// The plan in words — first whether it reaches its goal, said plainly when no set of the drawn
// poses does — and as CSV (robot,q1..qN,cameras) a robot program can read.
std::string PosePlanReport(const PosePlan& plan);
std::string PosePlanCsv(const PosePlan& plan);

}  // namespace cellmetry
