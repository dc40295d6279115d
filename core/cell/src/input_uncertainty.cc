// The inputs part of a cell's uncertainty (input_uncertainty.h).
#include "input_uncertainty.h"

#include <map>
#include <stdexcept>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/workcell_data.h"
#include "cellmetry/estimation/consider_covariance.h"

namespace cellmetry {
namespace {

// `spec` with its uncertain inputs free: the uncertain effects added (at zero), the robots'
// held model parameters with a stated sigma freed. Their parameter names and sigmas go to
// `input_sigma`.
WorkcellProblem WithInputsFree(const WorkcellProblem& spec,
                               std::map<std::string, double>* input_sigma) {
  WorkcellProblem augmented = spec;
  for (const auto& [effect, sigma] : spec.uncertain_inputs.effects) {
    augmented.effects.push_back(effect);
    for (const auto& p : effect.effect->parameters()) {
      (*input_sigma)[effect.name + "." + p.name] = sigma;
    }
  }
  for (auto& robot : augmented.robots) {
    const auto by_unit = spec.uncertain_inputs.model_sigma.find(robot.name);
    if (by_unit == spec.uncertain_inputs.model_sigma.end()) continue;
    for (auto& p : robot.model_parameters) {
      const auto sigma = by_unit->second.find(p.unit);
      if (!p.fixed || sigma == by_unit->second.end()) continue;  // estimated, or no sigma given
      p.fixed = false;
      (*input_sigma)[robot.name + ".model." + p.name] = sigma->second;
    }
  }
  return augmented;
}

}  // namespace

InputLink LinkInputs(const WorkcellProblem& spec, const Recording& recording,
                     const WorkcellData& data, const NoiseModel& noise,
                     const WorkcellEstimate& answer, const std::vector<std::string>& estimated) {
  InputLink link;
  if (spec.uncertain_inputs.empty() || estimated.empty()) return link;
  std::map<std::string, double> input_sigma;
  const WorkcellProblem augmented = WithInputsFree(spec, &input_sigma);
  // The same pairing (the inputs change no robot, target or camera), with what effects read.
  WorkcellData with_facts = data;
  if (with_facts.facts.empty()) with_facts.facts = GatherEffectFacts(augmented, recording);
  const auto assembled = AssembleWorkcell(augmented, recording, with_facts, noise, answer);
  NormalEquations at;
  if (!assembled->problem.EvaluateNormalEquations(&at)) {
    throw InputError({}, "the model cannot be evaluated at the answer with its uncertain inputs",
                     "Check the uncertain_inputs: section of the job");
  }
  link.sigma.resize(static_cast<Eigen::Index>(input_sigma.size()));
  for (const auto& [name, sigma] : input_sigma) {
    link.sigma[static_cast<Eigen::Index>(link.inputs.size())] = sigma;
    link.inputs.push_back(name);
  }
  link.estimated = estimated;
  link.cross = ConsiderCrossProduct(assembled->problem, at, estimated, link.inputs);
  return link;
}

void AddInputUncertainty(const InputLink& link, Uncertainty* u) {
  if (link.inputs.empty() || u->sigma.size() == 0) return;
  if (link.estimated != u->names) {
    throw std::logic_error("the uncertain inputs were linked at other free parameters than the "
                           "fit's");
  }
  const Eigen::MatrixXd bread = u->covariance / u->scale;
  const Eigen::MatrixXd cov = ConsiderCovariance(link.cross, bread, link.sigma);
  u->sigma_inputs = cov.diagonal().cwiseMax(0.0).cwiseSqrt();
  u->sigma = (u->sigma.cwiseAbs2() + u->sigma_inputs.cwiseAbs2()).cwiseSqrt();
}

}  // namespace cellmetry
