// Turning a recording into a workcell Problem.
//
// WorkcellData pairs the recording's observations with the robots and cameras once: which
// observations measure a carried target (a "tool" measurement), which measure the world target,
// and, for the per-frame model, the world-target pose seen in the same capture. Observations that
// cannot be used are counted with the reason.
//
// AssembleWorkcell builds a Problem over a subset of poses (for cross-validation) starting from
// a WorkcellEstimate; ReadEstimate reads the answer back out of it.
#pragma once

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "cellmetry/model/effect_context.h"
#include "cellmetry/estimation/noise_model.h"
#include "cellmetry/estimation/problem.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/cell/workcell_problem.h"

namespace cellmetry {

struct ToolMeasurement {
  int observation = 0;      // index in recording.observations
  int sample_index = 0;     // index in recording.samples
  int robot = 0;            // index in WorkcellProblem::robots
  int tool = 0;             // index in that robot's tools
  bool has_world_pose = false;
  Pose T_cam_world;         // the world target measured in the same capture (per-frame model)
};

struct WorkcellData {
  std::vector<ToolMeasurement> tools;
  std::vector<int> world_observations;          // indices of world-target observations
  std::map<std::string, int> skipped;           // reason -> count
  std::vector<SampleFacts> facts;               // per sample, when the problem has effects
};

// Pairs observations; raises InputError naming observations.csv when nothing is usable.
WorkcellData PrepareWorkcellData(const WorkcellProblem& spec, const Recording& recording);

struct AssembledWorkcell {
  Problem problem;
  std::vector<int> base_block;                  // per robot
  std::vector<int> model_block;                 // per robot
  std::vector<std::vector<int>> tool_block;     // per robot, per tool
  std::map<std::string, int> camera_block;      // static cameras
  std::vector<int> effect_block;                // per WorkcellProblem::effects entry
  // Starting rotations of each frame block (frame_block.h); block id -> R_ref.
  std::map<int, Eigen::Matrix3d> R_ref;
};

// `poses`: only captures of these pose ids are used; empty set = all.
std::unique_ptr<AssembledWorkcell> AssembleWorkcell(const WorkcellProblem& spec,
                                                    const Recording& recording,
                                                    const WorkcellData& data,
                                                    const NoiseModel& noise,
                                                    const WorkcellEstimate& start,
                                                    const std::set<int>& poses = {});

WorkcellEstimate ReadEstimate(const WorkcellProblem& spec, const AssembledWorkcell& assembled);

}  // namespace cellmetry
