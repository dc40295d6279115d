// WorkcellData: a recording's observations paired with a cell's robots and cameras, once.
//
// Which observations measure a carried target (a "tool" measurement), which measure the world
// target, and, for the per-frame model, the world-target pose seen in the same capture.
// Observations that cannot be used are counted with the reason; commands outside a robot's joint
// limits, or without a pose under its nominal model, are InputErrors at their samples.csv line.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/model/effect_context.h"

namespace cellmetry {

struct ToolMeasurement {
  int observation = 0;   // index in recording.observations
  int sample_index = 0;  // index in recording.samples
  int robot = 0;         // index in WorkcellProblem::robots
  int tool = 0;          // index in that robot's tools
  bool has_world_pose = false;
  Pose T_cam_world;  // the world target measured in the same capture (per-frame model)
};

struct WorkcellData {
  std::vector<ToolMeasurement> tools;
  std::vector<int> world_observations;  // indices of world-target observations
  std::map<std::string, int> skipped;   // reason -> count
  std::vector<SampleFacts> facts;       // per sample, when the problem has effects
};

// Pairs observations; raises InputError naming observations.csv when nothing is usable.
WorkcellData PrepareWorkcellData(const WorkcellProblem& spec, const Recording& recording);

// What effects read of each sample (WorkcellData::facts), at each robot's nominal model: the
// part of PrepareWorkcellData that depends on the job's effects, for data paired already.
std::vector<SampleFacts> GatherEffectFacts(const WorkcellProblem& spec, const Recording& recording);

}  // namespace cellmetry
