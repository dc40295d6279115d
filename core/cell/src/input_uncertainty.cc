// The inputs part of a cell's uncertainty (input_uncertainty.h).
#include "input_uncertainty.h"

#include <algorithm>
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

FitAnswer AnswerOf(const AssembledWorkcell& fit) {
  FitAnswer answer;
  const Problem& problem = fit.problem;
  for (int b = 0; b < problem.num_blocks(); ++b) {
    answer.block_values.emplace_back(problem.values(b),
                                     problem.values(b) + problem.block_parameters(b).size());
  }
  for (const FreeParameter& p : problem.free_parameters()) answer.estimated.push_back(p.name);
  answer.base_block = fit.base_block;
  answer.model_block = fit.model_block;
  answer.tool_block = fit.tool_block;
  answer.camera_block = fit.camera_block;
  answer.effect_block = fit.effect_block;
  answer.R_ref = fit.R_ref;
  return answer;
}

WorkcellEstimate ReferenceEstimate(const WorkcellProblem& spec, const AssembledWorkcell& fit) {
  WorkcellEstimate estimate = ReadEstimate(spec, fit);
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    const WorkcellRobot& robot = spec.robots[r];
    estimate.T_world_base[robot.name].R = fit.R_ref.at(fit.base_block[r]);
    for (size_t t = 0; t < robot.tools.size(); ++t) {
      estimate.T_flange_target[robot.tools[t].target].R = fit.R_ref.at(fit.tool_block[r][t]);
    }
  }
  for (const auto& [camera, block] : fit.camera_block) {
    estimate.T_world_cam[camera].R = fit.R_ref.at(block);
  }
  return estimate;
}

InputLinker::InputLinker(const WorkcellProblem& spec, const Recording& recording,
                         const WorkcellData& data, const NoiseModel& noise,
                         const WorkcellEstimate& start) {
  if (spec.uncertain_inputs.empty()) return;
  augmented_ = WithInputsFree(spec, &input_sigma_);
  // The same pairing (the inputs change no robot, target or camera), with what effects read.
  with_facts_ = data;
  if (with_facts_.facts.empty()) with_facts_.facts = GatherEffectFacts(augmented_, recording);
  assembled_ = AssembleWorkcell(augmented_, recording, with_facts_, noise, start);
}

namespace {

// Copies the fit's block `from` into the link's block `to` (the link's is as long or longer: the
// fit's effects come first in it).
void CopyBlock(const FitAnswer& fit, int from, int to, AssembledWorkcell* link) {
  if (from < 0 || to < 0) return;
  const auto R_fit = fit.R_ref.find(from);
  const auto R_link = link->R_ref.find(to);
  if ((R_fit == fit.R_ref.end()) != (R_link == link->R_ref.end()) ||
      (R_fit != fit.R_ref.end() && R_fit->second != R_link->second)) {
    throw std::logic_error(
        "the uncertain inputs' link was assembled at another start than the "
        "fit it is linked at");
  }
  const std::vector<double>& values = fit.block_values.at(static_cast<size_t>(from));
  if (values.size() > link->problem.block_parameters(to).size()) {
    throw std::logic_error("the uncertain inputs' link has a shorter block than the fit's");
  }
  std::copy(values.begin(), values.end(), link->problem.values(to));
}

}  // namespace

InputLink InputLinker::LinkAt(const FitAnswer& answer) {
  InputLink link;
  if (!assembled_ || answer.estimated.empty()) return link;
  for (size_t r = 0; r < answer.base_block.size(); ++r) {
    CopyBlock(answer, answer.base_block[r], assembled_->base_block.at(r), assembled_.get());
    CopyBlock(answer, answer.model_block[r], assembled_->model_block.at(r), assembled_.get());
    for (size_t t = 0; t < answer.tool_block[r].size(); ++t) {
      CopyBlock(answer, answer.tool_block[r][t], assembled_->tool_block.at(r).at(t),
                assembled_.get());
    }
  }
  for (const auto& [camera, block] : answer.camera_block) {
    CopyBlock(answer, block, assembled_->camera_block.at(camera), assembled_.get());
  }
  for (size_t k = 0; k < answer.effect_block.size(); ++k) {
    CopyBlock(answer, answer.effect_block[k], assembled_->effect_block.at(k), assembled_.get());
  }
  NormalEquations at;
  if (!assembled_->problem.EvaluateNormalEquations(&at)) {
    throw InputError({}, "the model cannot be evaluated at the answer with its uncertain inputs",
                     "Check the uncertain_inputs: section of the job");
  }
  link.sigma.resize(static_cast<Eigen::Index>(input_sigma_.size()));
  for (const auto& [name, sigma] : input_sigma_) {
    link.sigma[static_cast<Eigen::Index>(link.inputs.size())] = sigma;
    link.inputs.push_back(name);
  }
  link.estimated = answer.estimated;
  link.cross = ConsiderCrossProduct(assembled_->problem, at, link.estimated, link.inputs);
  return link;
}

void AddInputUncertainty(const InputLink& link, Uncertainty* u) {
  if (link.inputs.empty() || u->sigma.size() == 0) return;
  if (link.estimated != u->names) {
    throw std::logic_error(
        "the uncertain inputs were linked at other free parameters than the "
        "fit's");
  }
  Eigen::MatrixXd sensitivity;
  const Eigen::MatrixXd cov =
      ConsiderCovariance(link.cross, u->inverse_information, link.sigma, &sensitivity);
  u->input_effect = sensitivity * link.sigma.asDiagonal();
  u->input_names = link.inputs;
  u->sigma_inputs = cov.diagonal().cwiseMax(0.0).cwiseSqrt();
  u->sigma = (u->sigma.cwiseAbs2() + u->sigma_inputs.cwiseAbs2()).cwiseSqrt();
}

}  // namespace cellmetry
