// Turning a recording into a workcell Problem.
//
// The recording's observations are paired with the robots and cameras once (workcell_data.h).
//
// AssembleWorkcell builds a Problem over a subset of poses (for cross-validation) starting from
// a WorkcellEstimate; ReadEstimate reads the answer back out of it.
#pragma once

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "cellmetry/cell/workcell_data.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/estimation/noise_model.h"
#include "cellmetry/estimation/problem.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/model/effect_context.h"

namespace cellmetry {

// What one measurement residual block of an assembled workcell measured: the observation it
// compares with (an index into the recording's observations) and that observation's sample, pose,
// camera and target. The problem's ResidualInfo says how a block is weighed (its kind and sigma);
// this says what it is about, which only the cell layer knows.
struct MeasurementLabel {
  int observation = -1;
  int sample = -1;
  int pose = -1;
  std::string camera;
  std::string target;
};

struct AssembledWorkcell {
  Problem problem;
  // Per measurement residual block, in the problem's block order: what it measured. The blocks
  // from labels.size() on are the priors the problem's Build() adds, which measure nothing.
  std::vector<MeasurementLabel> labels;
  std::vector<int> base_block;               // per robot
  std::vector<int> model_block;              // per robot
  std::vector<std::vector<int>> tool_block;  // per robot, per tool
  std::map<std::string, int> camera_block;   // static cameras
  std::vector<int> effect_block;             // per WorkcellProblem::effects entry
  // Starting rotations of each frame block (frame_block.h); block id -> R_ref.
  std::map<int, Eigen::Matrix3d> R_ref;

  // Residual block `block`'s label; null for a prior.
  const MeasurementLabel* LabelOf(size_t block) const {
    return block < labels.size() ? &labels[block] : nullptr;
  }
};

// `poses`: only captures of these pose ids are used; empty set = all.
// The problem's residuals keep pointers into `spec` (robot models, effects) and `data` (each
// sample's facts for the effects): both must outlive the returned AssembledWorkcell.
std::unique_ptr<AssembledWorkcell> AssembleWorkcell(
    const WorkcellProblem& spec, const Recording& recording, const WorkcellData& data,
    const NoiseModel& noise, const WorkcellEstimate& start, const std::set<int>& poses = {});

WorkcellEstimate ReadEstimate(const WorkcellProblem& spec, const AssembledWorkcell& assembled);

}  // namespace cellmetry
