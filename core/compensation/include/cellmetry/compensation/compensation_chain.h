// CompensationChain: a calibrated robot as compensation evaluates it, and the tool's pose, its
// exact derivative in the joint commands and its uncertainty.
//
//   T_world_tool(q) = T_world_base * T_base_flange(q + dq(q), params) [flange effects] *
//                     T_flange_tool
//
// with dq the joint effects and the flange effects of the result's chain at their fitted values
// (model/effect_chain.h, the chain the fit and the simulator evaluate), each in the context of
// the command (effect_context.h: gravity torques and links at the robot config's nominal
// geometry, approach, payload, temperature, time). Measurement effects are left out: they change
// what a camera reports, not where the tool goes.
//
// The Jacobian in q is exact for the chain: q enters the model through its joint offset
// parameters (theta_i = q_i + offset_i, RobotModel::JointOffsetParameter), which carry Jet
// derivatives, so the model's own templated kinematics differentiates it. What the effects read
// from the context in double (gravity torques at q, sin(h q_i) of a gear error, a joint scale's
// q_i) is held at q: their share of the derivative, of the order of the effect's size relative
// to one (1e-3 for a compliance), is left out. A solve that uses it converges to the same
// answer, only not quadratically in that share (compensation.h checks the full chain at its end).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/joint_range.h"
#include "cellmetry/basics/transform.h"
#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/model/effect.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

// One of the chain's quantities the result's covariance may hold, and where it sits.
struct ChainParameter {
  std::string name;           // the result's name: "ur3.base.rx", "tool.z", "ur3.model.j2.d",
                              // "ur3.compliance_j3.j3.compliance"
  int covariance_index = -1;  // into ParameterCovariance (-1: held, not propagated)
};

struct CompensationChain {
  std::string robot;
  std::string tool;  // a frame on the flange, or "flange"
  std::shared_ptr<const RobotModel> model;
  std::vector<double> params;                          // the model's values (fitted)
  std::vector<double> nominal_params;                  // the robot config's: effect context
  std::vector<std::shared_ptr<const Effect>> effects;  // joint and flange stages
  std::vector<std::vector<double>> effect_values;      // per effect, parameters() order
  std::vector<std::string> effect_names;
  Pose T_world_base;
  Pose T_flange_tool;  // identity for "flange"
  Eigen::Vector3d gravity_base = Eigen::Vector3d(0, 0, -9.81);
  // Each joint's [min, max] (rad) over the calibration's samples; empty when the result does
  // not record them. A command beyond them extrapolates the calibration.
  JointRangesRad calibrated_joint_ranges_rad;
};

// What a command is evaluated with beside its joint values (effect_context.h).
struct CommandContext {
  std::vector<int> approach;  // per joint +1 / -1 / 0; empty: 0
  double payload_kg = 0.0;
  double temperature_c = NAN;
  double time_s = NAN;
};

// `robot`'s chain in `cell` ("" = the only one) with tool `tool` ("" = the robot's only tool,
// or the flange when it carries none; "flange" = the flange itself). InputError (naming
// result.json) for: a model without joint offset parameters, an effect of the chain the result
// does not record how to build, an unknown tool, several tools and none chosen.
CompensationChain ChainFromResult(const CalibratedCell& cell, const std::string& robot,
                                  const std::string& tool);

// The same robot as its config describes it: nominal model values, no effects; same base and
// tool. What a controller that knows only the nominal kinematics would command.
CompensationChain NominalChain(const CompensationChain& calibrated);

// T_world_tool at command `q`; false where the model has no pose there.
bool ToolPose(const CompensationChain& chain, const std::vector<double>& q,
              const CommandContext& context, Pose* T_world_tool);

// The same and d/dq (6 x joints): rows x y z (mm per rad), then the tool's rotation about the
// world's axes (omega, dR R^T = [omega]x d q). Exact as the header says.
bool ToolPoseJacobian(const CompensationChain& chain, const std::vector<double>& q,
                      const CommandContext& context, Pose* T_world_tool,
                      Eigen::Matrix<double, 6, Eigen::Dynamic>* J);

// The chain's quantities the result's covariance can hold, in a fixed order: the base (x y z rx
// ry rz), the tool, the model's parameters, the effects' parameters.
std::vector<ChainParameter> ChainParameters(const CompensationChain& chain,
                                            const ParameterCovariance& covariance);

// Covariance (6 x 6: x y z mm, rotation about the world's axes rad) of T_world_tool at `q`
// propagated to first order from `covariance` over the chain's quantities it holds (derivatives
// exact, by Jets). nullopt when it holds none of them or the model has no pose at q.
std::optional<Eigen::Matrix<double, 6, 6>> ToolPoseCovariance(
    const CompensationChain& chain, const std::vector<double>& q, const CommandContext& context,
    const ParameterCovariance& covariance);

}  // namespace cellmetry
