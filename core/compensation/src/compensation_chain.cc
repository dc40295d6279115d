// The calibrated chain compensation evaluates (compensation_chain.h).
#include "cellmetry/compensation/compensation_chain.h"

#include <algorithm>
#include <array>

#include "cellmetry/basics/error.h"
#include "cellmetry/model/effect_chain.h"
#include "cellmetry/model/effect_context.h"

namespace cellmetry {
namespace {

const char kRerun[] = "Run the job again with this cellmetry to write a result it can compensate";

// The facts of a command (effect_context.h) and the context pointing into them.
struct CommandFacts {
  SampleFacts facts;
  EffectContext context;
};

void MakeFacts(const CompensationChain& chain, const std::vector<double>& q,
               const CommandContext& command, CommandFacts* out) {
  out->facts = GeometricFacts(*chain.model, chain.nominal_params, q);
  out->facts.approach = command.approach;
  out->facts.approach.resize(q.size(), 0);
  out->facts.payload_kg = command.payload_kg;
  out->facts.temperature_c = command.temperature_c;
  out->facts.time_s = command.time_s;
  out->context = ContextOf(out->facts, chain.gravity_base);
}

// T_world_tool on scalar T: `base` and `tool` already on T, `model_params` and `effect_params`
// the chain's values (with whatever derivatives the caller seeded).
template <typename T>
bool ToolPoseT(const CompensationChain& chain, const EffectContext& context,
               const std::vector<T>& model_params, const std::vector<std::vector<T>>& effect_params,
               const Transform<T>& base, const Transform<T>& tool, Transform<T>* out) {
  std::vector<const Effect*> effects;
  std::vector<const T*> values;
  for (size_t k = 0; k < chain.effects.size(); ++k) {
    effects.push_back(chain.effects[k].get());
    values.push_back(effect_params[k].data());
  }
  Transform<T> flange;
  if (!FlangeWithEffects(*chain.model, model_params.data(), effects, values.data(), context,
                         &flange)) {
    return false;
  }
  *out = base * flange * tool;
  return true;
}

std::vector<Jet> Jets(const std::vector<double>& values) {
  return std::vector<Jet>(values.begin(), values.end());
}

std::vector<std::vector<Jet>> Jets(const std::vector<std::vector<double>>& values) {
  std::vector<std::vector<Jet>> out;
  for (const auto& v : values) out.push_back(Jets(v));
  return out;
}

// Column k of a Jet pose's derivative: position, then omega with dR R^T = [omega]x.
Eigen::Matrix<double, 6, 1> PoseDerivative(const Transform<Jet>& pose, int k) {
  Eigen::Matrix3d R, dR;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      R(r, c) = pose.R(r, c).a;
      dR(r, c) = pose.R(r, c).v[k];
    }
  }
  const Eigen::Matrix3d W = dR * R.transpose();
  Eigen::Matrix<double, 6, 1> column;
  column << pose.t[0].v[k], pose.t[1].v[k], pose.t[2].v[k], W(2, 1), W(0, 2), W(1, 0);
  return column;
}

Pose ValueOf(const Transform<Jet>& pose) {
  Pose out;
  for (int r = 0; r < 3; ++r) {
    out.t[r] = pose.t[r].a;
    for (int c = 0; c < 3; ++c) out.R(r, c) = pose.R(r, c).a;
  }
  return out;
}

// A frame moved by a Jet perturbation of its six entries (x y z, then a turn about the parent's
// axes), as the result's sigma reads them (frame_block.h): R' = Exp(d_r) R, t' = t + d_t.
Transform<Jet> Perturbed(const Pose& frame, const Jet* delta) {
  Transform<Jet> out = frame.cast<Jet>();
  out.R = RotationFromRvec(delta + 3) * out.R;
  for (int i = 0; i < 3; ++i) out.t[i] += delta[i];
  return out;
}

void CheckJointOffsets(const CalibratedCell& cell, const CalibratedRobot& robot) {
  const int n = robot.model->num_joints();
  if (n > kJetStride) {
    throw InputError({cell.json_path, 0, 0}, "robot '" + robot.name + "' has " + std::to_string(n) +
                                                 " joints; compensation handles up to " +
                                                 std::to_string(kJetStride));
  }
  for (int j = 0; j < n; ++j) {
    if (robot.model->JointOffsetParameter(j) < 0) {
      throw InputError({cell.json_path, 0, 0},
                       "robot model '" + robot.model_type + "' has no offset parameter for joint " +
                           std::to_string(j + 1) +
                           ", through which compensation differentiates its commands",
                       "Give the plugin JointOffsetParameter (robot_model.h)");
    }
  }
}

// The robot's joint and flange effects; every effect parameter the result fitted on the robot
// must belong to one the result can rebuild.
void AddEffects(const CalibratedCell& cell, const CalibratedRobot& robot,
                CompensationChain* chain) {
  std::vector<std::string> covered;
  for (const auto& e : cell.effects) {
    if (e.robot != robot.name || e.stage == "measurement") continue;
    if (!e.effect) {
      throw InputError({cell.json_path, 0, 0},
                       "the result does not record how effect '" + e.name +
                           "' was built (the job was built in memory)",
                       kRerun);
    }
    chain->effects.push_back(e.effect);
    chain->effect_names.push_back(e.name);
    std::vector<double> values;
    for (const auto& p : e.parameters) {
      values.push_back(p.value);
      covered.push_back(p.name);
    }
    chain->effect_values.push_back(values);
  }
  for (const auto& scalar : robot.effects) {
    if (std::find(covered.begin(), covered.end(), scalar.name) != covered.end()) continue;
    throw InputError({cell.json_path, 0, 0},
                     "the result fitted '" + scalar.name +
                         "' but does not record its effect (written by an older cellmetry)",
                     kRerun);
  }
}

// The tool frame on `robot`'s flange called `requested` ("" = the only one or the flange).
const CalibratedFrame* ChooseTool(const CalibratedCell& cell, const std::string& robot,
                                  const std::string& requested) {
  std::vector<const CalibratedFrame*> tools;
  std::string names = "flange";
  for (const auto& f : cell.frames) {
    if (f.parent != robot + ".flange") continue;
    tools.push_back(&f);
    names += ", " + f.name;
  }
  if (requested == "flange" || (requested.empty() && tools.empty())) return nullptr;
  if (requested.empty()) {
    if (tools.size() == 1) return tools.front();
    throw InputError({cell.json_path, 0, 0}, "robot '" + robot + "' carries several tools",
                     "Name one with --tool (" + names + ")");
  }
  for (const auto* t : tools) {
    if (t->name == requested) return t;
  }
  throw InputError({cell.json_path, 0, 0},
                   "robot '" + robot + "' carries no tool '" + requested + "'",
                   "Its tools: " + names);
}

}  // namespace

CompensationChain ChainFromResult(const CalibratedCell& cell, const std::string& robot_name,
                                  const std::string& tool_name) {
  const CalibratedRobot& robot = ChooseRobot(cell, robot_name);
  CheckJointOffsets(cell, robot);
  CompensationChain chain;
  chain.robot = robot.name;
  chain.model = robot.model;
  chain.params = robot.values;
  for (const auto& p : robot.model->parameters()) chain.nominal_params.push_back(p.nominal);
  if (const CalibratedFrame* base = FindFrame(cell, robot.name + ".base")) {
    chain.T_world_base = base->T_parent_frame;
  }
  const CalibratedFrame* tool = ChooseTool(cell, robot.name, tool_name);
  chain.tool = tool ? tool->name : "flange";
  if (tool) chain.T_flange_tool = tool->T_parent_frame;
  chain.gravity_base = cell.gravity_base;
  chain.calibrated_joint_ranges_rad = robot.joint_ranges_rad;
  AddEffects(cell, robot, &chain);
  return chain;
}

CompensationChain NominalChain(const CompensationChain& calibrated) {
  CompensationChain nominal = calibrated;
  nominal.params = calibrated.nominal_params;
  nominal.effects.clear();
  nominal.effect_values.clear();
  nominal.effect_names.clear();
  return nominal;
}

bool ToolPose(const CompensationChain& chain, const std::vector<double>& q,
              const CommandContext& context, Pose* T_world_tool) {
  CommandFacts facts;
  MakeFacts(chain, q, context, &facts);
  return ToolPoseT(chain, facts.context, chain.params, chain.effect_values, chain.T_world_base,
                   chain.T_flange_tool, T_world_tool);
}

bool ToolPoseJacobian(const CompensationChain& chain, const std::vector<double>& q,
                      const CommandContext& context, Pose* T_world_tool,
                      Eigen::Matrix<double, 6, Eigen::Dynamic>* J) {
  CommandFacts facts;
  MakeFacts(chain, q, context, &facts);
  std::vector<Jet> params = Jets(chain.params);
  const int n = chain.model->num_joints();
  for (int j = 0; j < n; ++j) params[chain.model->JointOffsetParameter(j)].v[j] = 1.0;
  Transform<Jet> pose;
  if (!ToolPoseT(chain, facts.context, params, Jets(chain.effect_values),
                 chain.T_world_base.cast<Jet>(), chain.T_flange_tool.cast<Jet>(), &pose)) {
    return false;
  }
  *T_world_tool = ValueOf(pose);
  J->resize(6, n);
  for (int j = 0; j < n; ++j) J->col(j) = PoseDerivative(pose, j);
  return true;
}

std::vector<ChainParameter> ChainParameters(const CompensationChain& chain,
                                            const ParameterCovariance& covariance) {
  std::vector<std::string> names;
  const std::string frames[] = {chain.robot + ".base", chain.tool};
  for (const std::string& frame : frames) {
    if (frame == "flange") continue;
    for (const char* entry : {"x", "y", "z", "rx", "ry", "rz"}) {
      names.push_back(frame + "." + entry);
    }
  }
  for (const auto& p : chain.model->parameters()) {
    names.push_back(chain.robot + ".model." + p.name);
  }
  for (size_t k = 0; k < chain.effects.size(); ++k) {
    for (const auto& p : chain.effects[k]->parameters()) {
      names.push_back(chain.effect_names[k] + "." + p.name);
    }
  }
  std::vector<ChainParameter> out;
  for (const auto& name : names) out.push_back({name, covariance.Find(name)});
  return out;
}

namespace {

// The Jets a ToolPoseCovariance pass seeds: the base's and tool's perturbations, the model's and
// the effects' values, laid out in ChainParameters' order.
struct SeededChain {
  std::array<Jet, 6> base_delta, tool_delta;
  std::vector<Jet> params;
  std::vector<std::vector<Jet>> effect_params;

  // The Jet of ChainParameters' entry `i`.
  Jet* Slot(const CompensationChain& chain, int i) {
    if (i < 6) return &base_delta[i];
    i -= 6;
    if (chain.tool != "flange") {
      if (i < 6) return &tool_delta[i];
      i -= 6;
    }
    if (i < static_cast<int>(params.size())) return &params[i];
    i -= static_cast<int>(params.size());
    for (auto& values : effect_params) {
      if (i < static_cast<int>(values.size())) return &values[i];
      i -= static_cast<int>(values.size());
    }
    return nullptr;
  }
};

}  // namespace

std::optional<Eigen::Matrix<double, 6, 6>> ToolPoseCovariance(
    const CompensationChain& chain, const std::vector<double>& q, const CommandContext& context,
    const ParameterCovariance& covariance) {
  const std::vector<ChainParameter> parameters = ChainParameters(chain, covariance);
  std::vector<int> propagated;
  for (size_t i = 0; i < parameters.size(); ++i) {
    if (parameters[i].covariance_index >= 0) propagated.push_back(static_cast<int>(i));
  }
  if (propagated.empty()) return std::nullopt;
  CommandFacts facts;
  MakeFacts(chain, q, context, &facts);
  const int m = static_cast<int>(propagated.size());
  Eigen::Matrix<double, 6, Eigen::Dynamic> G(6, m);
  for (int start = 0; start < m; start += kJetStride) {
    SeededChain seeded{{}, {}, Jets(chain.params), Jets(chain.effect_values)};
    const int count = std::min(kJetStride, m - start);
    for (int k = 0; k < count; ++k) seeded.Slot(chain, propagated[start + k])->v[k] = 1.0;
    Transform<Jet> pose;
    if (!ToolPoseT(chain, facts.context, seeded.params, seeded.effect_params,
                   Perturbed(chain.T_world_base, seeded.base_delta.data()),
                   Perturbed(chain.T_flange_tool, seeded.tool_delta.data()), &pose)) {
      return std::nullopt;
    }
    for (int k = 0; k < count; ++k) G.col(start + k) = PoseDerivative(pose, k);
  }
  Eigen::MatrixXd C(m, m);
  for (int a = 0; a < m; ++a) {
    for (int b = 0; b < m; ++b) {
      C(a, b) = covariance.covariance(parameters[propagated[a]].covariance_index,
                                      parameters[propagated[b]].covariance_index);
    }
  }
  return Eigen::Matrix<double, 6, 6>(G * C * G.transpose());
}

}  // namespace cellmetry
