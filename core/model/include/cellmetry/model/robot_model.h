// RobotModel: the contract of a robot-model plugin.
//
// A robot model maps controller joint readings q and its own named geometric parameters to the
// pose of the flange in the robot's base frame, T_base_flange. Base frame and tool offsets are not
// part of the model: the core owns them, for every robot alike.
//
// Derivatives are exact. A model is written once as a template on the scalar type and exposed
// through two virtual overloads, one for double and one for the Jet type the core's cost functions
// use (kJetStride derivatives per pass). Derive from RobotModelFromTemplate<YourModel> and give
// YourModel a
//
//   template <typename T>
//   bool ForwardT(const double* q, const T* params, Transform<T>* T_base_flange) const;
//
// returning false where the pose does not exist (e.g. a delta arm whose spheres do not meet).
//
// Arms whose flange only translates (delta arms) may also offer position inverse kinematics,
// which the kinematic calibration's joint-space ("inverse") residual and visual homing need:
// derive from InvertibleRobotModelFromTemplate<YourModel> and add
//
//   template <typename T>
//   bool InverseT(const T* flange_position_mm, const T* params, T* q) const;
//
// Both directions say why they failed through ForwardFailure / InverseFailure, for errors that a
// user can act on.
//
// For exports (`cellmetry export`, core/exports), a model may also describe itself as a chain of
// revolute joints (AsSerialChain, serial_chain.h: what URDF and vendors' kinematics files hold),
// with the names and frames of its own description when it has one (AsNamedChain), and write
// the robot config that rebuilds it at given parameter values (CalibratedConfig). The
// model knows its own geometry and config schema; the export knows the file formats; neither
// names the other.
#pragma once

#include <ceres/jet.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/parameter.h"
#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/model/named_chain.h"
#include "cellmetry/model/serial_chain.h"

namespace cellmetry {

// Derivatives carried per automatic-differentiation pass (ceres::DynamicAutoDiffCostFunction).
inline constexpr int kJetStride = 8;
using Jet = ceres::Jet<double, kJetStride>;

// A vertical cylinder about the base z axis where the flange may go (mm, base frame).
struct CylinderWorkspace {
  double radius_mm = 0.0;
  double z_min_mm = 0.0;
  double z_max_mm = 0.0;
};

// What the robot config says about where the robot can go and how finely it moves.
struct RobotLimits {
  std::vector<double> joint_min_rad;  // per joint; empty = unlimited
  std::vector<double> joint_max_rad;
  double joint_increment_rad = 0.0;  // one motor increment (2 pi / increments per rev); 0 = n/a
  std::optional<CylinderWorkspace> workspace;
};

// One link of a parallel arm between its moving platform and an arm (a delta's rod pair), in the
// base frame. Effects on the links (a tilted platform, ball-joint clearance) act through them.
struct ParallelLink {
  Eigen::Vector3d direction;  // unit, from the platform joint toward the arm's elbow
  Eigen::Vector3d pair_axis;  // unit, along which the parallelogram's two rods are spaced
};

class RobotModel {
 public:
  virtual ~RobotModel() = default;

  virtual int num_joints() const = 0;
  // The model's parameters with their nominal values (from the robot config) and default
  // fixed/free flags. Their order is the order of `params` in Forward().
  virtual const std::vector<Parameter>& parameters() const = 0;
  // Nominal flange -> tool transform from the robot config (identity when none is given).
  virtual Pose nominal_tool() const { return Pose::Identity(); }

  virtual bool Forward(const double* q, const double* params, Transform<double>* out) const = 0;
  virtual bool Forward(const double* q, const Jet* params, Transform<Jet>* out) const = 0;

  // The flange pose at (q, params) and how it moves with each model parameter: column k of
  // `twists` (6 x parameters().size()) is (d t / d p_k; w_k) in the base frame, where
  // d R / d p_k = [w_k]x R. What an analytic chain Jacobian needs from a model, at one
  // evaluation's cost. False where Forward fails. The default differentiates Forward on Jets
  // (kJetStride parameters per pass); a model with a closed form overrides it. Exact either way.
  virtual bool ForwardWithTwists(const double* q, const double* params, Pose* T_base_flange,
                                 Eigen::Matrix<double, 6, Eigen::Dynamic>* twists) const;

  // Index into parameters() of the angle added to joint i's reading (theta_i = q_i + param_i),
  // or -1 when the model has none. Joint effects (effect.h) act through it.
  virtual int JointOffsetParameter(int /*joint*/) const { return -1; }
  // The frame of every joint axis (z along the axis, origin on it), then the flange, in the base
  // frame at (q, params): num_joints() + 1 poses. False when the model has no such chain (a delta
  // arm's motors do not carry each other); effects that need gravity torques then cannot act.
  virtual bool JointFrames(const double* /*q*/, const double* /*params*/,
                           std::vector<Pose>* /*T_base_joint*/) const {
    return false;
  }

  // A parallel arm's links at (q, params), one per arm. False for serial arms.
  virtual bool ParallelLinks(const double* /*q*/, const double* /*params*/,
                             std::vector<ParallelLink>* /*links*/) const {
    return false;
  }

  // Warnings about the model's conditioning for what a job frees (`job_parameters`: this model's
  // parameters with the job's fixed flags), e.g. a length along near-parallel axes freed
  // without the tilt that keeps it well conditioned; for the report.
  virtual std::vector<std::string> Warnings(const std::vector<Parameter>& job_parameters) const {
    (void)job_parameters;
    return {};
  }
  virtual const RobotLimits& limits() const {
    static const RobotLimits none;
    return none;
  }
  // Why Forward failed at (q, params), in words for an error message.
  virtual std::string ForwardFailure(const double* q, const double* params) const;

  // Position inverse kinematics (optional): the joint values that put the flange at
  // `flange_position_mm` (base frame). False where the point is out of reach.
  virtual bool has_inverse() const { return false; }
  virtual bool Inverse(const double* flange_position_mm, const double* params, double* q) const;
  virtual bool Inverse(const Jet* flange_position_mm, const Jet* params, Jet* q) const;
  virtual std::string InverseFailure(const double* flange_position_mm, const double* params) const;

  // The model at `params` as a chain of revolute joints (serial_chain.h) whose ChainFlangePose
  // equals Forward at every q. False when the arm is not one (a delta arm's motors do not carry
  // each other): exports that need a chain (URDF, vendors' kinematics files) are then refused.
  virtual bool AsSerialChain(const double* /*params*/, SerialChain* /*chain*/) const {
    return false;
  }
  // The model at `params` as its own description names and frames it (named_chain.h: a URDF's
  // links and joints), whose NamedChainTipPose equals Forward at every q. False when the model
  // has no names of its own: exports then name the joints and links after the robot.
  virtual bool AsNamedChain(const double* /*params*/, NamedChain* /*chain*/) const { return false; }
  // The robot config (YAML text, the schema this model's plugin reads) that builds this model
  // with `params` as its nominal values, so that a calibration becomes the next job's robot.
  // `config` is the config the model was built from, for what the model does not keep (its name,
  // description, comments it may quote). "" when the plugin cannot write its config.
  virtual std::string CalibratedConfig(const ConfigNode& /*config*/,
                                       const double* /*params*/) const {
    return "";
  }
};

// Turns one templated ForwardT into both virtual overloads (CRTP).
template <typename Derived>
class RobotModelFromTemplate : public RobotModel {
 public:
  bool Forward(const double* q, const double* params, Transform<double>* out) const override {
    return static_cast<const Derived*>(this)->ForwardT(q, params, out);
  }
  bool Forward(const double* q, const Jet* params, Transform<Jet>* out) const override {
    return static_cast<const Derived*>(this)->ForwardT(q, params, out);
  }
};

// Adds position inverse kinematics from one templated InverseT (CRTP).
template <typename Derived>
class InvertibleRobotModelFromTemplate : public RobotModelFromTemplate<Derived> {
 public:
  bool has_inverse() const override { return true; }
  bool Inverse(const double* position, const double* params, double* q) const override {
    return static_cast<const Derived*>(this)->InverseT(position, params, q);
  }
  bool Inverse(const Jet* position, const Jet* params, Jet* q) const override {
    return static_cast<const Derived*>(this)->InverseT(position, params, q);
  }
};

}  // namespace cellmetry
