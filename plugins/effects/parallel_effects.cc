// Constructors, descriptions and the statics of the delta arm effects (platform_tilt.h,
// ball_joint_clearance.h).
#include "ball_joint_clearance.h"
#include "describe.h"
#include "platform_tilt.h"

namespace cellmetry::effects {
namespace {

std::string ArmsInWords(const std::vector<int>& arms) {
  std::string out = arms.size() == 1 ? "arm " : "arms ";
  for (size_t k = 0; k < arms.size(); ++k) out += (k ? ", " : "") + std::to_string(arms[k] + 1);
  return out;
}

std::vector<Parameter> PerArm(const std::vector<int>& arms, const std::string& what,
                              const std::string& unit, const std::string& doc, double plausible) {
  std::vector<Parameter> out;
  for (int i : arms) {
    out.push_back(
        {"arm" + std::to_string(i + 1) + "." + what, unit, 0.0, false, {}, {}, {}, doc, plausible});
  }
  return out;
}

// The links as columns: rod directions U, and the rows (e_i x u_i) of the tilt constraint.
bool Links(const EffectContext& context, Eigen::Matrix3d* U, Eigen::Matrix3d* A) {
  if (!context.links || context.links->size() != 3) return false;
  for (int i = 0; i < 3; ++i) {
    const ParallelLink& link = (*context.links)[i];
    U->col(i) = link.direction;
    A->row(i) = link.pair_axis.cross(link.direction).transpose();
  }
  return true;
}

}  // namespace

PlatformTilt::PlatformTilt(std::vector<int> arms)
    : ParallelLinkEffect(arms, PerArm(arms, "skew", "rad",
                                      "parallelogram rod length difference over the rod spacing",
                                      0.02)) {}  // 1 mm over 50 mm of spacing

std::string PlatformTilt::Describe(const std::vector<double>& params) const {
  return WithParameters(ArmsInWords(arms_) + " parallelogram out of true (platform tilt)",
                        parameters_, params);
}

bool PlatformTilt::TiltPerSkew(const EffectContext& context, Eigen::Matrix3d* tilt_per_skew) {
  Eigen::Matrix3d U, A;
  if (!Links(context, &U, &A)) return false;
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
  if (!lu.isInvertible()) return false;  // rods in a singular configuration
  *tilt_per_skew = lu.inverse();
  return true;
}

BallJointClearance::BallJointClearance(std::vector<int> arms)
    : ParallelLinkEffect(arms, PerArm(arms, "clearance", "mm",
                                      "ball-joint play along the rods, taken up at a full share "
                                      "of the load",
                                      1.0)) {                       // mm: a worn joint
  for (Parameter& p : parameters_) p.plausible_nonnegative = true;  // play is never negative
}

std::string BallJointClearance::Describe(const std::vector<double>& params) const {
  return WithParameters(ArmsInWords(arms_) + " ball-joint clearance along the rod force",
                        parameters_, params);
}

bool BallJointClearance::MovePerClearance(const EffectContext& context,
                                          Eigen::Matrix3d* move_per_clearance) {
  Eigen::Matrix3d U, A;
  if (!Links(context, &U, &A) || !(context.gravity_base.norm() > 0)) return false;
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(U);
  if (!lu.isInvertible()) return false;
  const Eigen::Vector3d share = lu.solve(-context.gravity_base.normalized());
  // u_i . dp = -c_i s_i for all i: dp = -U^-T diag(s) c.
  *move_per_clearance = -U.transpose().inverse() * share.asDiagonal();
  return true;
}

}  // namespace cellmetry::effects
