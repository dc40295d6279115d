// The physics finder's default candidates (diagnosis.h): what every effect plugin offers for the
// cell (model/effect_candidates.h), each built through the registry. The finder names no effect:
// which effects a cell can have, on which joint or camera, is the plugins' to say.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "cellmetry/diagnosis/diagnosis.h"

namespace cellmetry {
namespace {

// What an offer may know of the cell: its robots, the recording's cameras and targets, what the
// job states and the diagnosis options that shape the candidates.
CandidateCell CellOf(const WorkcellProblem& spec, const Recording& recording,
                     const DiagnosisOptions& options) {
  CandidateCell cell;
  for (const WorkcellRobot& robot : spec.robots) {
    cell.robots.push_back({robot.name, robot.model.get()});
    cell.level_stated |= robot.level_sigma_rad.has_value();
  }
  cell.cameras = recording.cameras;
  for (const auto& [target, carrier] : recording.targets) cell.targets.push_back(target);
  cell.world_target = spec.world_target;
  cell.use_tool_rotation = spec.use_tool_rotation;
  for (const auto& s : recording.samples) {
    cell.temperatures |= s.temperature_c.has_value();
    cell.times |= s.time_s.has_value();
  }
  cell.link_masses_kg = options.link_masses_kg;
  cell.gear_harmonics = options.gear_harmonics;
  cell.joint_couplings = options.joint_couplings;
  cell.group_candidates = options.group_candidates;
  return cell;
}

const WorkcellRobot& RobotNamed(const WorkcellProblem& spec, const OfferedCandidate& offered) {
  for (const WorkcellRobot& robot : spec.robots) {
    if (robot.name == offered.robot) return robot;
  }
  throw std::runtime_error("an effect plugin offered the candidate " + offered.name +
                           " on robot '" + offered.robot + "', which the cell does not have");
}

CandidateEffect Build(const OfferedCandidate& offered, const WorkcellRobot& robot,
                      Registry& registry) {
  const ConfigNode config = ConfigNode::LoadString(offered.config, "default candidates");
  CandidateEffect c;
  c.type = config["type"].AsString();
  c.effect.name = offered.name;
  c.effect.robot = robot.name;
  c.effect.effect = registry.CreateEffect(c.type, config, *robot.model);
  c.effect.config = config.FlowText();
  c.label = offered.label;
  c.data_hint = offered.data_hint;
  c.site = CandidateSite(config, robot.name);
  c.family = offered.family;
  c.group = offered.group;
  c.group_label = offered.group_label;
  c.atoms = offered.atoms;
  c.frame = offered.frame;
  return c;
}

}  // namespace

std::vector<CandidateEffect> DefaultCandidates(const WorkcellProblem& spec,
                                               const Recording& recording,
                                               const DiagnosisOptions& options,
                                               Registry& registry) {
  const CandidateCell cell = CellOf(spec, recording, options);
  std::vector<CandidateEffect> out;
  for (const CandidateOffer& offer : registry.candidate_offers()) {
    for (const OfferedCandidate& offered : offer(cell)) {
      out.push_back(Build(offered, RobotNamed(spec, offered), registry));
    }
  }
  return out;
}

}  // namespace cellmetry
