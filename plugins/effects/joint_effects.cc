// Constructors and descriptions of the joint effects (joint_compliance.h, backlash.h,
// transmission_error.h, joint_scale.h, joint_coupling.h).
#include "backlash.h"
#include "describe.h"
#include "joint_compliance.h"
#include "joint_coupling.h"
#include "joint_scale.h"
#include "joint_selection.h"
#include "transmission_error.h"

namespace cellmetry::effects {

JointCompliance::JointCompliance(std::vector<int> joints, std::vector<double> link_masses_kg)
    : joints_(std::move(joints)), link_masses_kg_(std::move(link_masses_kg)) {
  for (int j : joints_) {
    parameters_.push_back({JointName(j) + ".compliance",
                           "rad/(N m)",
                           0.0,
                           false,
                           {},
                           {},
                           {},
                           "joint deflection per N m of gravity torque",
                           {}});
    parameters_.back().plausible = 5e-4;  // a joint softer than 2,000 N m/rad is unusual
    parameters_.back().plausible_nonnegative = true;  // a joint gives with gravity, not against
  }
}

std::string JointCompliance::Describe(const std::vector<double>& params) const {
  return WithParameters(JointsInWords(joints_) + " compliance under gravity", parameters_, params);
}

Backlash::Backlash(std::vector<int> joints, std::vector<double> link_masses_kg, double hold_nm)
    : joints_(std::move(joints)), link_masses_kg_(std::move(link_masses_kg)), hold_nm_(hold_nm) {
  for (int j : joints_) {
    parameters_.push_back({JointName(j) + ".backlash",
                           "rad",
                           0.0,
                           false,
                           {},
                           {},
                           {},
                           "play in the gear train (the joint lags by half of it)",
                           {}});
    parameters_.back().plausible = 5e-3;  // 0.3 deg: spur gears; harmonic drives far less
    // A joint lags where it came from, or gives with gravity.
    parameters_.back().plausible_nonnegative = true;
  }
}

std::string Backlash::Describe(const std::vector<double>& params) const {
  return WithParameters(JointsInWords(joints_) + " backlash" +
                            (held_by_gravity() ? ", held against one flank by gravity" : ""),
                        parameters_, params);
}

TransmissionError::TransmissionError(std::vector<int> joints, std::vector<int> harmonics)
    : joints_(std::move(joints)), harmonics_(std::move(harmonics)) {
  for (int j : joints_) {
    for (int h : harmonics_) {
      const std::string name = JointName(j) + ".h" + std::to_string(h);
      parameters_.push_back({name + ".sin",
                             "rad",
                             0.0,
                             false,
                             {},
                             {},
                             {},
                             "transmission error, sine of harmonic " + std::to_string(h),
                             {}});
      parameters_.back().plausible = 2e-3;  // harmonic drives 0.3 mrad, cycloidal 1 mrad
      parameters_.push_back({name + ".cos",
                             "rad",
                             0.0,
                             false,
                             {},
                             {},
                             {},
                             "transmission error, cosine of harmonic " + std::to_string(h),
                             {}});
      parameters_.back().plausible = 2e-3;  // as the sine
    }
  }
}

std::string TransmissionError::Describe(const std::vector<double>& params) const {
  return WithParameters(JointsInWords(joints_) + " gear transmission error", parameters_, params);
}

JointScale::JointScale(std::vector<int> joints) : joints_(std::move(joints)) {
  for (int j : joints_) {
    parameters_.push_back({JointName(j) + ".scale",
                           "1",
                           0.0,
                           false,
                           {},
                           {},
                           {},
                           "relative error of the gear ratio",
                           {}});
    parameters_.back().plausible = 5e-3;  // half a percent of gear ratio
  }
}

std::string JointScale::Describe(const std::vector<double>& params) const {
  return WithParameters(JointsInWords(joints_) + " gear ratio (joint scale) error", parameters_,
                        params);
}

JointCoupling::JointCoupling(std::vector<int> driven_joints, int driving_joint)
    : driven_joints_(std::move(driven_joints)), driving_joint_(driving_joint) {
  for (int j : driven_joints_) {
    parameters_.push_back({JointName(j) + ".coupling_" + JointName(driving_joint_),
                           "1",
                           0.0,
                           false,
                           {},
                           {},
                           {},
                           "rad it turns per rad of joint " + std::to_string(driving_joint_ + 1),
                           {}});
    parameters_.back().plausible = 5e-3;  // as a gear ratio's error
  }
}

std::string JointCoupling::Describe(const std::vector<double>& params) const {
  return WithParameters(
      JointsInWords(driven_joints_) + " coupled to joint " + std::to_string(driving_joint_ + 1),
      parameters_, params);
}

}  // namespace cellmetry::effects
