// `cellmetry diagnose JOB.yaml`: a workcell job (job.h) with an optional `diagnosis:` section.
//
//   diagnosis:
//     alpha: 0.01            # family-wise error rate of every test
//     bootstrap: 40          # resamples of poses
//     bootstrap_share: 0.8   # how often their selection must include the chosen effect
//     alias_correlation: 0.99  # candidates this alike here are one finding with two names
//     folds: 10              # blocked cross-validation by pose
//     max_effects: 4
//     min_poses: 20
//     link_masses_kg: [2.0, 3.42, 1.26, 0.8, 0.8, 0.35]   # the gravity-torque regressor
//     gear_harmonics: [3, 7] # of the drives: joined to 1 and 2 in each joint's transmission
//     joint_couplings: [[5, 6]]  # joints the drives couple (driving, driven): offered too
//     candidate candidates:            # default: the whole library on every joint and camera
//       - {type: backlash, joints: [2]}
//
// Output: <job output>/diagnosis/{report.txt, diagnosis.json, result.json of the final fit}.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/cell/job.h"
#include "cellmetry/diagnosis/diagnosis.h"

namespace cellmetry {

struct DiagnosisJob {
  WorkcellJob workcell;
  DiagnosisOptions options;
  std::vector<ConfigNode> candidate_configs;  // empty: DefaultCandidates
};

DiagnosisJob LoadDiagnosisJob(const std::string& path, Registry& registry,
                              bool recording_must_exist = true);

// The job's candidates: its own list (each named "<robot>.<type>_<k>") or the defaults.
std::vector<CandidateEffect> JobCandidates(const DiagnosisJob& job, const Recording& recording,
                                           Registry& registry);

}  // namespace cellmetry
