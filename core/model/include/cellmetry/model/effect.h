// Effect: the contract of an effect plugin, a named piece of physics the geometric model leaves
// out (joint compliance under gravity, backlash, gear transmission error, thermal growth, depth
// bias, ...) with its parameters and units. Effects compose with any robot model and with the
// measurement model; the physics finder (diagnosis.h) adds them one at a time.
//
// An effect acts at one stage of the prediction chain
//
//   q --[kJoint]--> T_base_flange(q + dq) --[kFlange]--> T_cam_target --[kMeasurement]--> measured
//
//   kJoint        adds dq (rad) to the joint angles. The core adds it through the robot model's
//                 joint offset parameters (RobotModel::JointOffsetParameter), so every model that
//                 has them (serial MDH offsets, delta homing) composes with every joint effect.
//   kFlange       moves and turns the flange in the base frame (mm, rotation matrix): thermal
//                 growth of the links, a delta platform tilted by its parallelograms.
//   kMeasurement  changes a target position predicted in a camera frame (mm): depth bias, a
//                 detector's systematic error.
//
// How much it acts depends on the sample (EffectContext): joint readings, the direction each
// joint last moved (backlash), the joint frames (gravity torques), time, temperature, payload,
// camera, a parallel arm's links (delta rods). A zero parameter vector is always "no effect".
//
// Derivatives are exact: an effect is written once as a template on the scalar type and exposed
// through a double and a Jet overload. Derive from EffectFromTemplate<YourEffect> and give it
//
//   template <typename T>
//   void ApplyT(const EffectContext& context, const T* params, T* values) const;
//
// with `values` the stage's quantity: kJoint dq[num_joints] (zero on entry; add to it), kFlange
// the flange position p_base_flange[3] followed by its rotation R_base_flange[9], column-major,
// kMeasurement the target position p_cam[3] followed by its rotation R_cam_target[9] (modify
// either).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "cellmetry/basics/parameter.h"
#include "cellmetry/basics/transform.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

enum class EffectStage { kJoint, kFlange, kMeasurement };

// What the recording and the nominal geometry say about one sample (effect_context.h fills it).
struct EffectContext {
  int num_joints = 0;
  const double* q = nullptr;      // joint readings, rad
  const int* approach = nullptr;  // per joint: +1 / -1, the sign of its last move into
                                  // this pose in capture order; 0 before it first moved
  const std::vector<Pose>* T_base_joint = nullptr;   // joint i's frame (z = its axis) at nominal
                                                     // geometry, then the flange; empty when the
                                                     // robot model has no joint frames
  const std::vector<ParallelLink>* links = nullptr;  // a parallel arm's links at nominal
                                                     // geometry; empty for serial arms
  const Eigen::Matrix3Xd* flange_jacobian_mm = nullptr;  // d p_flange / d q (mm/rad) at
                                                         // nominal geometry, for models without
                                                         // joint frames; empty otherwise
  Eigen::Vector3d gravity_base = Eigen::Vector3d(0, 0, -9.81);  // m/s^2, in the base frame
  double time_s = NAN;
  double temperature_c = NAN;
  double payload_kg = 0.0;
  std::string camera;  // kMeasurement: the camera of the observation
  std::string target;  // kMeasurement: the target it measured
};

// What an effect needs from a recording; the diagnosis calls an effect untestable, and says what
// to record, when the recording lacks it.
struct EffectNeeds {
  bool joint_frames = false;  // gravity torques (joint frames, or a flange Jacobian)
  bool approach = false;      // capture order with moves in both directions
  bool time = false;
  bool temperature = false;
  bool payload = false;
  bool parallel_links = false;  // a parallel arm (RobotModel::ParallelLinks)
};

class Effect {
 public:
  virtual ~Effect() = default;

  virtual EffectStage stage() const = 0;
  // Named parameters ("j2.c", "cam1.depth_scale") with units; zero means no effect.
  virtual const std::vector<Parameter>& parameters() const = 0;
  virtual EffectNeeds needs() const { return {}; }
  // What is physically left out, in a few plain words ("joint 2 compliance under gravity").
  virtual std::string Describe(const std::vector<double>& params) const = 0;

  virtual void Apply(const EffectContext& context, const double* params, double* values) const = 0;
  virtual void Apply(const EffectContext& context, const Jet* params, Jet* values) const = 0;
};

// Turns one templated ApplyT into both virtual overloads (CRTP).
template <typename Derived>
class EffectFromTemplate : public Effect {
 public:
  void Apply(const EffectContext& context, const double* params, double* values) const override {
    static_cast<const Derived*>(this)->ApplyT(context, params, values);
  }
  void Apply(const EffectContext& context, const Jet* params, Jet* values) const override {
    static_cast<const Derived*>(this)->ApplyT(context, params, values);
  }
};

// A lumped point mass: kg, and where it sits (m, base frame).
struct LumpedMass {
  double kg = 0.0;
  Eigen::Vector3d at_m = Eigen::Vector3d::Zero();
};

// The arm as lumped point masses: link i's mass halfway between joint i's origin and the next
// joint's (the flange's for the last link), then the payload at the flange; num_joints + 1 of
// them. `T_base_joint` has num_joints + 1 frames (EffectContext), mm; a link without a mass in
// `link_masses_kg` weighs nothing.
std::vector<LumpedMass> LumpedMasses(const std::vector<Pose>& T_base_joint,
                                     const std::vector<double>& link_masses_kg, double payload_kg);

// Gravity torque about each joint axis (N m) of the arm's LumpedMasses; gravity in m/s^2, base
// frame. A positive torque turns the joint in its positive direction.
std::vector<double> GravityTorques(const std::vector<Pose>& T_base_joint,
                                   const std::vector<double>& link_masses_kg, double payload_kg,
                                   const Eigen::Vector3d& gravity_base);

// Gravity torques (N m) of a load of `mass_kg` at the flange, through the flange position's
// Jacobian (mm/rad): tau = J^T m g (virtual work). For arms without joint frames (a delta, whose
// motors do not carry each other), where the moving mass hangs on the flange.
std::vector<double> FlangeLoadTorques(const Eigen::Matrix3Xd& flange_jacobian_mm, double mass_kg,
                                      const Eigen::Vector3d& gravity_base);

// The gravity torques a sample offers: GravityTorques from its joint frames; without them,
// FlangeLoadTorques with the links' masses and the payload at the flange; empty when neither.
std::vector<double> ContextGravityTorques(const EffectContext& context,
                                          const std::vector<double>& link_masses_kg);

}  // namespace cellmetry
