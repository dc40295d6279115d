// The physics finder's proof (`compare: physics`): recordings with one hidden effect each, at a
// set signal-to-noise ratio of the effect's unabsorbed part, diagnosed (diagnosis.h); how often
// the right effect is named, how often a clean recording gets a false claim, whether physics
// outside the library is reported as unexplained, and the held-out RMS against the floor.
//
//   compare: physics
//   seeds: 5                                              # runs per case
//   snr: 6                                                # of the unabsorbed part, whitened
//   cells:                                                # one per robot cell
//     - name: UR3
//       simulation: ../simulations/ur3_physics_base.yaml  # the cell, poses and noise (no effects)
//       job: ../jobs/ur3_diagnose.yaml                    # the diagnosis job (recording unused)
//       cases:
//         - {name: clean, expect: none}
//         - {name: joint 2 compliance, expect: ur3.compliance_j2,
//            effect: {type: joint_compliance, joints: [2]}}          # a library effect, or
//         - {name: camera bumped, expect: unexplained,
//            concealed: {kind: camera_bump, camera: cam1}}           # concealed_physics.h
//   output: ../../docs/physics.md   # between <!-- physics-suite:begin/end --> (WritePhysicsSuite)
//
// Each finished case is kept in <output>.partial.json; an interrupted run resumes from there
// (cases with the same cell, name, seeds and SNR), and the file goes when the suite is done.
//
// The SNR: the case's effect at a trial size is simulated without noise and the geometry fitted
// to every observation of it (no outlier test: the mismatch is the signal); what the geometry
// cannot absorb is left in the whitened residuals, whose norm scales linearly with the effect's
// size. The size is set so that this norm is `snr`.
//
// The oracle beside each effect case: the same noise-free recording at that size gives the
// Bayes choice among the candidates of an oracle that knows one effect of this size is there and
// the noise's sigma (oracle_selection.h), drawn 4,000 times: how often the poses let the right
// effect be the most probable one, and the SNR over every row, which it reports as it sees it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/diagnosis/oracle_selection.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

struct SuiteCase {
  std::string name;
  std::string expect;                   // a candidate's name, "none" or "unexplained"
  std::optional<ConfigNode> effect;     // a library effect, all parameters equal at trial size
  std::optional<ConfigNode> concealed;  // or physics outside the library's equations
};

struct SuiteCell {
  std::string name;        // "UR3"
  std::string simulation;  // workcell simulation without effects
  std::string job;         // diagnosis job
  std::vector<SuiteCase> cases;
};

struct PhysicsSuiteSpec {
  std::string file;
  int seeds = 5;
  double snr = 6.0;
  std::vector<SuiteCell> cells;
  std::string output;
};

PhysicsSuiteSpec LoadPhysicsSuite(const std::string& path);

struct SuiteRun {
  std::string named;   // first accepted effect, "none" or "unexplained"
  std::string failed;  // when none was accepted: the tests the best candidate failed
  double held_out_over_floor = 0.0;
  double seconds = 0.0;
  std::vector<std::string> aliases;    // the named effect's exact aliases (candidate names)
  std::string group;                   // the named effect's group (CandidateEffect::group), or ""
  std::vector<std::string> tied = {};  // none named: the two tied at one site (TiedCandidates)
};

struct SuiteCaseResult {
  std::string cell;
  SuiteCase spec;
  double magnitude = 0.0;  // the effect size giving the SNR
  std::vector<SuiteRun> runs;
  // The oracle's Bayes choice on the first seed's poses (oracle_selection.h): how often the poses
  // let the right physics be the most probable candidate. No draws for clean and outside-library
  // cases.
  OracleSelection oracle;
  int right() const;  // runs that named what was expected
  // Whether `run` named what was expected: the finding's name, one of its exact aliases or its
  // group.
  bool named_right(const SuiteRun& run) const;
};

std::vector<SuiteCaseResult> RunPhysicsSuite(const PhysicsSuiteSpec& spec, Registry& registry);

// Refuses (InputError) an output that exists without the markers "<!-- physics-suite:begin -->"
// and "<!-- physics-suite:end -->": a document cellmetry did not write would be lost. Run it
// before the suite, so that the refusal comes before the work.
void CheckPhysicsSuiteOutput(const std::string& path);

// Writes the suite's markdown to `path`: between the markers, the rest of the document kept, or
// as a new file holding the markers and the tables between them (so that the next run replaces
// only the tables). Atomic; refuses what CheckPhysicsSuiteOutput refuses.
void WritePhysicsSuite(const PhysicsSuiteSpec& spec, const std::string& path,
                       const std::string& markdown);

// Rates with their 95 % intervals and verdicts against the targets, the decisions, the cases,
// the confusion matrix and the held-out RMS, as markdown (physics_suite_report.cc).
std::string PhysicsSuiteMarkdown(const PhysicsSuiteSpec& spec,
                                 const std::vector<SuiteCaseResult>& results);

// One line per question the suite answers: is the right effect named (>= 90 %), do clean
// recordings stay clean (>= 95 %), is physics outside the library called unexplained (all), does
// the accepted model bring the held-out RMS to the floor (<= 1.2); then per cell, the cases whose
// rate is shown below 90 % and what was named instead. Each says met, missed or undecided, and
// for undecided how many runs at the observed rate would decide.
std::vector<std::string> PhysicsSuiteRecommendations(const PhysicsSuiteSpec& spec,
                                                     const std::vector<SuiteCaseResult>& results);

}  // namespace cellmetry
