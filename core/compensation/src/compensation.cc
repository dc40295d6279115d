// Compensate (compensation.h): every target in file order, with its seed, approach, joint-limit
// check, the nominal command it replaces and the predicted remaining error with its sigma.
#include "cellmetry/compensation/compensation.h"
#include "short_number.h"

#include <cmath>
#include <cstdio>
#include <tuple>

namespace cellmetry {
namespace {

// What a target asks for: a tool position, and its rotation when it fixes one.
struct WantedPose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  std::optional<Eigen::Matrix3d> R;
};

// A joint target is where the nominal kinematics puts the tool; it fixes the rotation only for
// an arm that can turn its tool at will (six joints or more).
std::optional<WantedPose> Wanted(const CompensationChain& nominal,
                                 const CompensationTarget& target) {
  WantedPose wanted;
  if (target.kind != CompensationTarget::Kind::kJoints) {
    wanted.p = target.p_world_tool_mm;
    if (target.kind == CompensationTarget::Kind::kPose) wanted.R = target.R_world_tool;
    return wanted;
  }
  Pose T;
  if (!ToolPose(nominal, target.q_rad, CommandContext{}, &T)) return std::nullopt;
  wanted.p = T.t;
  if (nominal.model->num_joints() >= 6) wanted.R = T.R;
  return wanted;
}

// Where the solve starts, or why it cannot (compensation.h).
std::optional<std::vector<double>> Seed(const CompensationChain& chain,
                                        const CompensationTarget& target, const WantedPose& wanted,
                                        const std::vector<double>& previous, std::string* why_not) {
  if (!target.q_rad.empty()) return target.q_rad;
  if (chain.model->has_inverse()) {
    // A flange that only translates: the tool's offset is a shift of the flange.
    const Eigen::Vector3d p_base = chain.T_world_base.inverse() * wanted.p;
    const Eigen::Vector3d p_flange = p_base - chain.T_flange_tool.t;
    std::vector<double> q(chain.model->num_joints());
    if (chain.model->Inverse(p_flange.data(), chain.params.data(), q.data())) return q;
    *why_not = "out of reach: " + chain.model->InverseFailure(p_flange.data(), chain.params.data());
    return std::nullopt;
  }
  if (!previous.empty()) return previous;
  *why_not = "no seed: the arm has no closed-form inverse and this is the first target";
  *why_not += "; give q1_rad ... joint values near the configuration meant on this row";
  return std::nullopt;
}

// "" or why `q` is past (or within `margin` of) a joint limit of the robot config.
std::string PastJointLimit(const RobotModel& model, const std::vector<double>& q, double margin) {
  const RobotLimits& limits = model.limits();
  for (size_t j = 0; j < q.size() && j < limits.joint_min_rad.size(); ++j) {
    const double lo = limits.joint_min_rad[j], hi = limits.joint_max_rad[j];
    if (q[j] >= lo + margin && q[j] <= hi - margin) continue;
    const bool low = q[j] < lo + margin;
    return "past joint limits: joint " + std::to_string(j + 1) + " would need " +
           ShortNumber(q[j]) + " rad, " + (low ? "below" : "above") + " its limit " +
           ShortNumber(low ? lo : hi) + " rad" +
           (margin > 0 ? " less the margin " + ShortNumber(margin) + " rad" : "");
  }
  return "";
}

// Per joint: the sign of the move from `previous` to `q`, or `running`'s where it does not move.
std::vector<int> ApproachInto(const std::vector<double>& q, const std::vector<double>& previous,
                              const std::vector<int>& running) {
  std::vector<int> approach = running;
  for (size_t j = 0; j < q.size() && j < previous.size(); ++j) {
    const double move = q[j] - previous[j];
    if (std::abs(move) > 1e-9) approach[j] = move > 0 ? 1 : -1;
  }
  return approach;
}

CommandContext ContextOf(const CompensationTarget& target, const std::vector<int>& approach) {
  return {approach, target.payload_kg, target.temperature_c, target.time_s};
}

// The error of command `q` under `chain` against the wanted pose: mm and rad (NaN: no rotation
// wanted, or no pose at q).
std::pair<double, double> ErrorOf(const CompensationChain& chain, const std::vector<double>& q,
                                  const CommandContext& context, const WantedPose& wanted) {
  Pose T;
  if (!ToolPose(chain, q, context, &T)) return {NAN, NAN};
  return {(T.t - wanted.p).norm(), wanted.R ? RotationError(T.R, *wanted.R).norm() : NAN};
}

// Where the commands so far leave the robot: the last command sent and each joint's approach.
struct History {
  std::vector<double> previous;
  std::vector<int> approach;
};

SolvedCommand SolveWithApproach(const CompensationChain& chain, const CompensationTarget& target,
                                const WantedPose& wanted, const std::vector<double>& seed,
                                const History& history, const CompensationOptions& options,
                                std::vector<int>* approach) {
  const Eigen::Matrix3d* R = wanted.R ? &*wanted.R : nullptr;
  if (!target.approach.empty()) {
    *approach = target.approach;
    return SolveCommand(chain, wanted.p, R, seed, ContextOf(target, *approach), options);
  }
  *approach = ApproachInto(seed, history.previous, history.approach);
  SolvedCommand solved =
      SolveCommand(chain, wanted.p, R, seed, ContextOf(target, *approach), options);
  const std::vector<int> own = ApproachInto(solved.q_rad, history.previous, history.approach);
  if (solved.reached && own != *approach) {  // its own move differs from the seed's: once more
    *approach = own;
    solved = SolveCommand(chain, wanted.p, R, solved.q_rad, ContextOf(target, own), options);
  }
  return solved;
}

void Predict(const CompensationChain& chain, const CompensationTarget& target,
             const WantedPose& wanted, const std::vector<double>& seed,
             const ParameterCovariance& covariance, const CompensationOptions& options,
             CompensatedCommand* out) {
  const CommandContext context = ContextOf(target, out->approach);
  const auto pose_covariance = ToolPoseCovariance(chain, out->q_rad, context, covariance);
  if (pose_covariance) {
    out->sigma_mm = std::sqrt(pose_covariance->topLeftCorner<3, 3>().trace());
    if (wanted.R) out->sigma_rad = std::sqrt(pose_covariance->bottomRightCorner<3, 3>().trace());
  }
  const CompensationChain nominal = NominalChain(chain);
  std::vector<double> q_nominal = target.q_rad;
  if (target.kind != CompensationTarget::Kind::kJoints) {
    const SolvedCommand n =
        SolveCommand(nominal, wanted.p, wanted.R ? &*wanted.R : nullptr, seed, context, options);
    if (!n.reached) return;
    q_nominal = n.q_rad;
  }
  std::tie(out->uncompensated_mm, out->uncompensated_rad) =
      ErrorOf(chain, q_nominal, context, wanted);
}

CompensatedCommand CompensateOne(const CompensationChain& chain, const CompensationTarget& target,
                                 const ParameterCovariance& covariance,
                                 const CompensationOptions& options, History* history) {
  CompensatedCommand out;
  out.target = &target;
  const auto wanted_or = Wanted(NominalChain(chain), target);
  if (!wanted_or) {
    out.refused = true;
    out.reason = "the robot config's nominal kinematics has no pose at these joint values: " +
                 chain.model->ForwardFailure(target.q_rad.data(), chain.nominal_params.data());
    return out;
  }
  const WantedPose& wanted = *wanted_or;
  std::string why_not;
  const auto seed = Seed(chain, target, wanted, history->previous, &why_not);
  if (!seed) {
    out.refused = true;
    out.reason = why_not;
    return out;
  }
  const SolvedCommand solved =
      SolveWithApproach(chain, target, wanted, *seed, *history, options, &out.approach);
  out.iterations = solved.iterations;
  out.error_mm = solved.error_mm;
  out.error_rad = solved.error_rad;
  out.reason = solved.reached
                   ? PastJointLimit(*chain.model, solved.q_rad, options.joint_limit_margin_rad)
                   : solved.failure;
  out.refused = !out.reason.empty();
  if (out.refused) return out;
  out.q_rad = solved.q_rad;
  history->previous = out.q_rad;
  history->approach = out.approach;
  Predict(chain, target, wanted, *seed, covariance, options, &out);
  return out;
}

}  // namespace

std::vector<CompensatedCommand> Compensate(const CompensationChain& chain,
                                           const std::vector<CompensationTarget>& targets,
                                           const ParameterCovariance& covariance,
                                           const CompensationOptions& options) {
  History history;
  history.approach.assign(chain.model->num_joints(), 0);
  std::vector<CompensatedCommand> commands;
  for (const auto& target : targets) {
    commands.push_back(CompensateOne(chain, target, covariance, options, &history));
    CompensatedCommand& command = commands.back();
    if (!command.refused) {
      command.joints_beyond_calibration =
          JointsOutsideRanges(chain.calibrated_joint_ranges_rad, command.q_rad);
    }
  }
  return commands;
}

}  // namespace cellmetry
