// The result's description of a cell's estimate (workcell_description.h): frames and
// parameters with their sigma parts, robot and effect models.
#include "workcell_description.h"

#include <algorithm>
#include <vector>

#include "cellmetry/formats/config_node.h"

namespace cellmetry {
namespace {

// The total sigma of a free parameter and its parts; all zero where it is not free.
struct SigmaOf {
  double total = 0.0, statistical = 0.0, systematic = 0.0, inputs = 0.0;
  bool free = false;
};

SigmaOf Sigma(const Uncertainty& u, const std::string& name) {
  const auto it = std::find(u.names.begin(), u.names.end(), name);
  if (it == u.names.end()) return {};
  const auto i = it - u.names.begin();
  SigmaOf s;
  s.total = s.statistical = u.sigma[i];
  s.free = true;
  if (u.sigma_statistical.size() == u.sigma.size()) s.statistical = u.sigma_statistical[i];
  if (u.sigma_systematic.size() == u.sigma.size()) s.systematic = u.sigma_systematic[i];
  if (u.sigma_inputs.size() == u.sigma.size()) s.inputs = u.sigma_inputs[i];
  return s;
}

// The parameters whose values a hold decides: each held parameter with partners (no gauge prior
// on it), and those partners.
std::set<std::string> Undetermined(const std::vector<UnidentifiableParameter>& unidentifiable) {
  std::set<std::string> names;
  for (const auto& u : unidentifiable) {
    if (u.prior_sigma > 0.0 || u.moves_with.empty() || !u.convention.empty()) continue;
    names.insert(u.name);
    for (const auto& partner : u.moves_with) names.insert(partner.name);
  }
  return names;
}

FrameEstimate MakeFrame(const std::string& name, const std::string& parent, const Pose& pose,
                        const Uncertainty& u, const std::set<std::string>& undetermined) {
  FrameEstimate frame;
  frame.name = name;
  frame.parent = parent;
  frame.pose = pose;
  for (int i = 0; i < 6; ++i) {
    const SigmaOf sigma = Sigma(u, name + "." + kFrameParameterNames[i]);
    (i < 3 ? frame.sigma_mm[i] : frame.sigma_rad[i - 3]) = sigma.total;
    frame.sigma_statistical[i] = sigma.statistical;
    frame.sigma_systematic[i] = sigma.systematic;
    frame.sigma_inputs[i] = sigma.inputs;
    frame.held[i] = !sigma.free;
    frame.undetermined[i] = undetermined.count(name + "." + kFrameParameterNames[i]) > 0;
  }
  return frame;
}

const char* StageName(const Effect& effect) {
  switch (effect.stage()) {
    case EffectStage::kJoint: return "joint";
    case EffectStage::kFlange: return "flange";
    case EffectStage::kMeasurement: return "measurement";
  }
  return "";
}

// A model or effect parameter's estimate.
ScalarEstimate MakeScalar(const std::string& name, const std::string& unit, double nominal,
                          double value, const Uncertainty& u, const std::set<std::string>& held,
                          const std::set<std::string>& undetermined,
                          const std::vector<UnidentifiableParameter>& unidentifiable = {}) {
  ScalarEstimate s;
  s.name = name;
  s.unit = unit;
  s.nominal = nominal;
  s.value = value;
  s.held = held.count(name) > 0;
  const SigmaOf sigma = Sigma(u, name);
  s.sigma = sigma.total;
  s.sigma_statistical = sigma.statistical;
  s.sigma_systematic = sigma.systematic;
  s.sigma_inputs = sigma.inputs;
  s.undetermined = undetermined.count(name) > 0;
  for (const UnidentifiableParameter& p : unidentifiable) {
    if (p.name == name) s.convention = p.convention;
  }
  return s;
}

// `robot`'s frames (its base, then each carried target), free model parameters and model.
void DescribeRobot(const WorkcellRobot& robot, const std::set<std::string>& held,
                   const std::set<std::string>& undetermined, WorkcellResult* result) {
  const Uncertainty& u = result->uncertainty;
  const WorkcellEstimate& e = result->estimate;
  result->frames.push_back(
      MakeFrame(robot.name + ".base", "world", e.T_world_base.at(robot.name), u, undetermined));
  for (const auto& tool : robot.tools) {
    result->frames.push_back(MakeFrame(tool.target, robot.name + ".flange",
                                       e.T_flange_target.at(tool.target), u, undetermined));
  }
  const auto& values = e.model.at(robot.name);
  for (size_t i = 0; i < robot.model_parameters.size(); ++i) {
    const Parameter& p = robot.model_parameters[i];
    if (p.fixed) continue;
    result->model_parameters.push_back(MakeScalar(robot.name + ".model." + p.name, p.unit,
                                                  p.nominal, values[i], u, held, undetermined,
                                                  result->unidentifiable));
  }
  RobotModelRecord record{
      robot.name, robot.model_file, robot.model_config, robot.model_parameters, {}};
  for (size_t i = 0; i < record.parameters.size(); ++i) record.parameters[i].nominal = values[i];
  result->robot_models.push_back(std::move(record));
}

// Each effect's model (its type read off its configuration) and fitted parameters.
void DescribeEffects(const WorkcellProblem& spec, const std::set<std::string>& held,
                     const std::set<std::string>& undetermined, WorkcellResult* result) {
  for (const WorkcellEffect& effect : spec.effects) {
    result->effect_models.push_back(
        {effect.name, effect.robot, "", StageName(*effect.effect), effect.config});
    if (!effect.config.empty()) {
      result->effect_models.back().type =
          ConfigNode::LoadString(effect.config, effect.name)["type"].AsString();
    }
    const auto& params = effect.effect->parameters();
    const auto& values = result->estimate.effects.at(effect.name);
    for (size_t i = 0; i < params.size(); ++i) {
      result->model_parameters.push_back(MakeScalar(effect.name + "." + params[i].name,
                                                    params[i].unit, 0.0, values[i],
                                                    result->uncertainty, held, undetermined));
    }
  }
}

}  // namespace

void DescribeEstimate(const WorkcellProblem& spec, const std::set<std::string>& held,
                      WorkcellResult* result) {
  const std::set<std::string> undetermined = Undetermined(result->unidentifiable);
  for (const WorkcellRobot& robot : spec.robots) {
    DescribeRobot(robot, held, undetermined, result);
  }
  for (const auto& [camera, pose] : result->estimate.T_world_cam) {
    result->frames.push_back(MakeFrame(camera, "world", pose, result->uncertainty, undetermined));
  }
  result->gravity_base = spec.gravity_base;
  DescribeEffects(spec, held, undetermined, result);
}

}  // namespace cellmetry
