// SerialMdhModel's non-template parts (serial_mdh_model.h): the per-joint parameters, and a
// warning where consecutive axes are parallel and modified DH is ill-conditioned.
#include "serial_mdh_model.h"

#include <cmath>
#include <sstream>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/exact_number.h"

namespace cellmetry::serial_mdh {

namespace {

// Where the data cannot determine a parameter, what holding it at nominal puts where
// (Parameter::convention): joint 1's entries put the base frame and the last joint's d and
// offset the flange frame (a free base, camera or tool absorbs them); a Hayati tilt between
// axes that are not parallel, and where the common normal meets two parallel axes, are the
// parametrisation's own redundancies (Hayati & Mirmirani 1985).
std::string Convention(size_t joint, size_t joints, int entry, bool parallel_to_previous) {
  const std::string axis = "joint " + std::to_string(joint + 1);
  if (joint == 0) return "with joint 1's axis it puts the base frame";
  if (joint + 1 == joints && (entry == kD || entry == kOffset)) {
    return "with " + axis + "'s axis it puts the flange frame";
  }
  if (entry == kBeta && !parallel_to_previous) {
    return "zero in modified DH where the axes of joints " + std::to_string(joint) + " and " +
           std::to_string(joint + 1) + " are not parallel";
  }
  if (entry == kD && parallel_to_previous) {
    return "where the axes of joints " + std::to_string(joint) + " and " +
           std::to_string(joint + 1) + " are parallel, where the common normal stands on them";
  }
  return "";
}

bool ParallelToPrevious(const Joint& joint) { return std::abs(std::sin(joint.alpha)) < 1e-3; }

}  // namespace

SerialMdhModel::SerialMdhModel(std::vector<Joint> joints) : joints_(std::move(joints)) {
  for (size_t i = 0; i < joints_.size(); ++i) {
    const std::string j = "j" + std::to_string(i + 1) + ".";
    const Joint& joint = joints_[i];
    const bool parallel = i > 0 && ParallelToPrevious(joint);
    parameters_.push_back({j + "alpha",
                           "rad",
                           joint.alpha,
                           true,
                           {},
                           {},
                           {},
                           "twist about x_{i-1} (Craig alpha_{i-1})",
                           {}});
    parameters_.push_back(
        {j + "a", "mm", joint.a, true, {}, {}, {}, "length along x_{i-1} (Craig a_{i-1})", {}});
    parameters_.push_back({j + "beta",
                           "rad",
                           joint.beta,
                           true,
                           {},
                           {},
                           {},
                           "Hayati tilt about y; use for parallel axes",
                           {}});
    parameters_.push_back({j + "d", "mm", joint.d, true, {}, {}, {}, "offset along z_i", {}});
    parameters_.push_back({j + "offset",
                           "rad",
                           joint.offset,
                           true,
                           {},
                           {},
                           {},
                           "joint zero offset added to the reading",
                           {}});
    for (int entry = 0; entry < kParamsPerJoint; ++entry) {
      parameters_[kParamsPerJoint * i + entry].convention =
          Convention(i, joints_.size(), entry, parallel);
    }
  }
}

std::vector<std::string> SerialMdhModel::Warnings(
    const std::vector<Parameter>& job_parameters) const {
  std::vector<std::string> warnings;
  auto is_free = [&](size_t joint, int entry) {
    const size_t k = kParamsPerJoint * joint + static_cast<size_t>(entry);
    return k < job_parameters.size() && !job_parameters[k].fixed;
  };
  for (size_t i = 1; i < joints_.size(); ++i) {
    if (ParallelToPrevious(joints_[i]) && is_free(i, kD) && !is_free(i, kBeta)) {
      warnings.push_back("axes of joints " + std::to_string(i) + " and " + std::to_string(i + 1) +
                         " are parallel: modified DH is ill-conditioned there; identify j" +
                         std::to_string(i + 1) + ".beta (Hayati) rather than j" +
                         std::to_string(i + 1) + ".d");
    }
  }
  return warnings;
}

bool SerialMdhModel::ForwardWithTwists(const double* q, const double* params, Pose* T_base_flange,
                                       Eigen::Matrix<double, 6, Eigen::Dynamic>* twists) const {
  // A = Rx(alpha) Tx(a) Ry(beta) Rz(q + offset) Tz(d): each factor moves what follows it about
  // or along one axis of the frame it starts from (base coordinates).
  struct Motion {
    Eigen::Vector3d axis, point;  // unit axis; a point on it (a turn's centre)
    bool turn = false;
  };
  thread_local std::vector<Motion> motions;  // reused: no allocation per evaluation
  motions.resize(kParamsPerJoint * joints_.size());
  Pose chain = Pose::Identity();
  for (size_t i = 0; i < joints_.size(); ++i) {
    const double* p = params + kParamsPerJoint * i;
    Motion* m = &motions[kParamsPerJoint * i];
    const Eigen::Vector3d x = chain.R.col(0);
    m[kAlpha] = {x, chain.t, true};
    m[kA] = {x, chain.t, false};  // Rx(alpha) keeps x
    const Eigen::Vector3d origin = chain.t + p[kA] * x;
    const double ca = std::cos(p[kAlpha]), sa = std::sin(p[kAlpha]);
    const double cb = std::cos(p[kBeta]), sb = std::sin(p[kBeta]);
    const Eigen::Matrix3d& R = chain.R;
    m[kBeta] = {R * Eigen::Vector3d(0.0, ca, sa), origin, true};           // y after Rx(alpha)
    const Eigen::Vector3d z = R * Eigen::Vector3d(sb, -sa * cb, ca * cb);  // z after Ry(beta)
    m[kOffset] = {z, origin, true};
    m[kD] = {z, origin, false};  // Rz(theta) keeps z
    chain = chain * Link(p[kAlpha], p[kA], p[kBeta], q[i] + p[kOffset], p[kD]);
  }
  *T_base_flange = chain;
  twists->resize(6, static_cast<Eigen::Index>(motions.size()));
  for (size_t k = 0; k < motions.size(); ++k) {
    const Motion& m = motions[k];
    const Eigen::Index column = static_cast<Eigen::Index>(k);
    if (m.turn) {
      twists->col(column) << m.axis.cross(chain.t - m.point), m.axis;
    } else {
      twists->col(column) << m.axis, Eigen::Vector3d::Zero();
    }
  }
  return true;
}

bool SerialMdhModel::AsSerialChain(const double* params, SerialChain* chain) const {
  chain->T_parent_joint.clear();
  for (size_t i = 0; i < joints_.size(); ++i) {
    const double* p = params + kParamsPerJoint * i;
    chain->T_parent_joint.push_back(Link(p[kAlpha], p[kA], p[kBeta], p[kOffset], p[kD]));
  }
  chain->T_last_joint_flange = Pose::Identity();
  chain->not_expressible.clear();
  return true;
}

std::string SerialMdhModel::CalibratedConfig(const ConfigNode& config, const double* params) const {
  std::ostringstream out;
  out << "type: serial_mdh\n";
  CopyTextEntry(config, "name", out);
  CopyTextEntry(config, "description", out);
  out << "units: {length: mm, angle: rad}\n"
      << "joints:                 # Craig's alpha_{i-1}, a_{i-1} on joint i's row; Hayati beta\n";
  for (size_t i = 0; i < joints_.size(); ++i) {
    const double* p = params + kParamsPerJoint * i;
    out << "  - {alpha: " << ExactNumber(p[kAlpha]) << ", a: " << ExactNumber(p[kA])
        << ", beta: " << ExactNumber(p[kBeta]) << ", d: " << ExactNumber(p[kD])
        << ", offset: " << ExactNumber(p[kOffset]) << "}\n";
  }
  return out.str();
}

}  // namespace cellmetry::serial_mdh
