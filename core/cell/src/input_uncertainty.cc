// The inputs part of a cell's uncertainty (input_uncertainty.h).
#include "input_uncertainty.h"

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

void AddInputUncertainty(const WorkcellProblem& spec, const Recording& recording,
                         const NoiseModel& noise, const WorkcellEstimate& answer, Uncertainty* u) {
  if (spec.uncertain_inputs.empty() || u->sigma.size() == 0) return;
  std::map<std::string, double> input_sigma;
  const WorkcellProblem augmented = WithInputsFree(spec, &input_sigma);
  const WorkcellData data = PrepareWorkcellData(augmented, recording);
  const auto assembled = AssembleWorkcell(augmented, recording, data, noise, answer);
  NormalEquations at;
  const bool valid = assembled->problem.EvaluateNormalEquations(&at);
  const Eigen::MatrixXd bread = u->covariance / u->scale;
  const Eigen::MatrixXd cov = ConsiderCovariance(assembled->problem, valid ? &at : nullptr,
                                                 u->names, bread, input_sigma);
  u->sigma_inputs = cov.diagonal().cwiseMax(0.0).cwiseSqrt();
  u->sigma = (u->sigma.cwiseAbs2() + u->sigma_inputs.cwiseAbs2()).cwiseSqrt();
}

}  // namespace cellmetry
