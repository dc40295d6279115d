// The held-out check a calibration engineer runs: the same robot recorded in another setup (a
// job's `validation: {held_out_setup}`), days later, the instrument set up anew and the probe
// mounted again. The robot's calibrated geometry (its model entries and effects, at the
// calibration's answer) is kept; the frames a new setup changes -- every frame the job frees:
// the instrument's (camera's) pose, the probe's (tool's) on the flange, a base where a world
// target defines the world -- are registered again on a stated few poses, and the other poses
// are scored: prediction - measurement of each carried target's position, with its predicted
// sigma. The nominal model registered on the same poses is the baseline.
//
// Predicted covariance of a scored point p (all in the camera frame, mm):
//
//   C_p = G_p S G_p^T + N
//
// G_p the prediction's Jacobian over the calibrated entries theta and the registered frames phi;
// N the registration's per-axis noise variance (where the job gives no sigma, the new setup's
// scatter about the calibrated model, estimated from the registration poses' residuals: what the
// model leaves out of each point; a stated sigma is widened by the registration rows' reduced
// chi-square where it exceeds 1, as S_phi|theta below); S the joint covariance of (theta, phi).
// theta's is the calibration's (its correlations, each scaled to its total sigma); the registration
// carries theta's error into phi through phi(theta): A = d phi / d theta = -(J_phi^T J_phi)^-1
// J_phi^T J_theta (its whitened Jacobians), so
//
//   S = [ S_tt      S_tt A^T                ]
//       [ A S_tt    A S_tt A^T + S_phi|theta ],   S_phi|theta = (J_phi^T J_phi)^-1 scaled
//
// by the registration rows' reduced chi-square where above 1. A point is within its 95 % ellipsoid
// where e^T C_p^-1 e <= 7.815 (chi-square, 3 degrees of freedom): about 95 % of the points
// when the sigma are honest.
//
// The RMS is itself an estimate from the scored poses, and carries its standard error (the
// delta method over the points' squared errors, statistics.h); two models scored on the same
// poses compare by the paired standard error of their difference (RmsGainStandardError). Both
// take the poses as independent draws (a pose's points, its cameras and repeated captures, count
// together: statistics.h's grouped form): the error the registration leaves in the frames is
// shared by every point and is not in them.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/estimation/solver.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

// Which poses of the held-out recording register the new setup's frames (pose ids, as in its
// samples.csv); exactly one of the three is set.
struct RegistrationPoses {
  int first = 0;           // the first N poses in capture order
  int every = 0;           // every k-th pose in capture order, from the first
  std::vector<int> poses;  // these pose ids
};

struct HeldOutSetupSpec {
  std::string recording;  // the folder
  RegistrationPoses register_on;
};

// The registration poses `register_on` names in `recording` (pose ids, capture order). Throws
// InputError at `where` when it names a pose the recording does not have, or leaves fewer than
// one pose to score.
std::vector<int> SelectRegistrationPoses(const Recording& recording,
                                         const RegistrationPoses& register_on,
                                         const SourceLocation& where);

// The held-out check of `result` (identified by `spec` on `calibration`) on `held_out`,
// registering on `poses`; its points beyond the calibration's joint ranges marked and summed
// apart (joint_ranges.h).
HeldOutSetupScore ScoreHeldOutSetup(const WorkcellProblem& spec, const WorkcellResult& result,
                                    const Recording& calibration, const Recording& held_out,
                                    const std::vector<int>& poses, const SolverMaker& make_solver);

// Each scored point's squared 3D error, |e|^2, in the score's order.
std::vector<double> SquaredErrors(const HeldOutSetupScore& score);

// The standard error of before.rms_mm - after.rms_mm: the same points scored by two models
// (paired, statistics.h). Throws std::invalid_argument unless both scored the same points.
double RmsGainStandardError(const HeldOutSetupScore& before, const HeldOutSetupScore& after);

}  // namespace cellmetry
