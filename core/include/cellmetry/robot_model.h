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
#pragma once

#include <ceres/jet.h>

#include <memory>
#include <string>
#include <vector>

#include "cellmetry/parameter.h"
#include "cellmetry/transform.h"

namespace cellmetry {

// Derivatives carried per automatic-differentiation pass (ceres::DynamicAutoDiffCostFunction).
inline constexpr int kJetStride = 8;
using Jet = ceres::Jet<double, kJetStride>;

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

  // Warnings about the model's conditioning (e.g. near-parallel axes), for the report.
  virtual std::vector<std::string> Warnings() const { return {}; }
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

}  // namespace cellmetry
