// Compensation: the joint commands that put a calibrated robot's tool where it is wanted, under
// its calibrated geometry and every effect of its result (`cellmetry compensate`).
//
// For each target (compensation_targets.h) SolveCommand finds q_cmd with
//
//   T_world_tool(q_cmd) = target        (compensation_chain.h: calibrated geometry and effects,
//                                        in the target's context: payload, approach,
//                                        temperature, time)
//
// by Levenberg-Marquardt on the residual [p - p_target (mm); w Log(R R_target^T) (rad)] (w =
// rotation_weight_mm_per_rad; position only when the target gives no rotation), its Jacobian
// exact for the chain (ToolPoseJacobian, checked against central differences in
// test_compensate). Seeded from the target's own joint values (a joint target, or the seed
// columns), else the model's inverse kinematics (a delta), else the previous target's command.
//
// A target is refused, with the reason in words, when
//   - the robot has no pose there (ForwardFailure / InverseFailure of the model),
//   - the solve ends farther than `tolerance_mm` / `tolerance_rad` from it: out of reach (the
//     closest the calibrated robot came is reported),
//   - the command lies past a joint limit of the robot config, or within
//     `joint_limit_margin_rad` of it,
//   - a serial arm's first target has no seed (which configuration is meant is the user's call).
//
// Beside every command: the remaining error the calibrated model predicts for it (the solve's
// leftover), its sigma propagated from the result's covariance (ToolPoseCovariance: base, tool,
// the freed model and effect parameters), and the error the command the robot config's nominal
// kinematics alone would give makes under the calibrated model (what compensation removes).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/compensation/compensation_chain.h"
#include "cellmetry/compensation/compensation_targets.h"

namespace cellmetry {

struct CompensationOptions {
  // A target counts as reached when the solve ends this close to it. 1 um and 1 urad: far below
  // any arm's repeatability, far above the solve's own rounding (~1e-10 mm).
  double tolerance_mm = 1e-3;
  double tolerance_rad = 1e-6;
  // Levenberg-Marquardt iterations per target (a reachable target takes 3-10 from a seed within
  // a few degrees).
  int max_iterations = 100;
  // Commands closer than this to a joint limit of the robot config are refused (rad). 0: only
  // past the limit.
  double joint_limit_margin_rad = 0.0;
  // How many mm a rad of tool rotation error weighs in the solve's cost (the answer of a
  // reachable target does not depend on it; the path to it and the closest approach to an
  // unreachable one do).
  double rotation_weight_mm_per_rad = 100.0;
  // A step of the solve turns no joint by more than this (rad): it stays in the configuration
  // the seed is in.
  double max_step_rad = 0.3;
};

// The outcome of one solve.
struct SolvedCommand {
  bool reached = false;
  std::string failure;        // why not, in words ("" when reached)
  std::vector<double> q_rad;  // the command (the closest one when not reached)
  double error_mm = NAN;      // |p(q) - p_target| under the chain
  double error_rad = NAN;     // |Log(R(q) R_target^T)|; NaN for a position target
  int iterations = 0;
};

// Solves for the command that puts `chain`'s tool at `target` (its pose, or only its position
// when `R_world_tool` is null) from `seed`, in `context`.
SolvedCommand SolveCommand(const CompensationChain& chain, const Eigen::Vector3d& p_world_tool,
                           const Eigen::Matrix3d* R_world_tool, const std::vector<double>& seed,
                           const CommandContext& context, const CompensationOptions& options);

struct CompensatedCommand {
  const CompensationTarget* target = nullptr;
  bool refused = false;
  std::string reason;                         // why refused ("" otherwise)
  std::vector<double> q_rad;                  // the command (empty when refused)
  std::vector<int> approach;                  // the approach it was solved for
  double error_mm = NAN, error_rad = NAN;     // remaining, predicted by the calibrated chain
  std::optional<double> sigma_mm, sigma_rad;  // its sigma: sqrt of the pose covariance's
                                              // position / rotation trace
  double uncompensated_mm = NAN, uncompensated_rad = NAN;  // the nominal command's error
  int iterations = 0;
  // The joints (1-based) the command puts beyond the calibration's ranges
  // (CompensationChain::calibrated_joint_ranges_rad, JointsOutsideRanges): there the
  // calibrated model is extrapolated, and `sigma_*` holds only what it contains.
  std::vector<int> joints_beyond_calibration;
};

// Every target in file order; the approach of a target without approach columns is the sign of
// each joint's move from the previous target's command (a joint that does not move keeps its
// sign; 0 before the first move), solved again once if its own command changes it.
std::vector<CompensatedCommand> Compensate(const CompensationChain& chain,
                                           const std::vector<CompensationTarget>& targets,
                                           const ParameterCovariance& covariance,
                                           const CompensationOptions& options);

}  // namespace cellmetry
