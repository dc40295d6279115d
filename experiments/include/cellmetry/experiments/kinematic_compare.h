// The 2023 report's Table 7, for any pose sets, sizes, formulations and solvers: calibrate a
// simulated arm (one drawn truth) on each pose set and score the answer on fresh positions.
// Each calibration is the one cell pipeline (workcell.h) on the simulation's problem.
//
// Compare spec (YAML, `compare: kinematic`):
//   simulation: <simulation spec>                # the arm without a world target, its camera,
//                                                # truth errors, noise, seed
//   pose_sets: [camera_view, uniform_workspace, boundaries]
//   sizes: [24, 64, 125]
//   formulations: [inverse, forward]             # the report's words: joint-space, Cartesian
//   solvers: {<label>: <solver block>, ...}       # e.g. lm: {type: ceres_lm}
//   validation_points: 200
//   seeds: 10                                    # repetitions of every row (default 10): seed 0
//                                                # is the simulation's own truth and draw, each
//                                                # further seed a fresh truth and pose set drawn
//                                                # around it; rows then read mean [95 % t-interval]
//                                                # with a recommendation per pose set and size
//   output: <folder for table.md and table.csv>
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "cellmetry/cell/prediction.h"
#include "cellmetry/cell/workcell_simulation.h"

namespace cellmetry {

struct CompareSpec {
  std::string file;
  WorkcellSimulationSpec simulation;
  std::vector<PoseSet> pose_sets;
  std::vector<int> sizes;
  std::vector<ResidualForm> formulations;
  std::vector<std::pair<std::string, ConfigNode>> solvers;  // label, solver block
  int validation_points = 200;
  int seeds = 10;
  std::string output;
};

struct CompareRow {
  PoseSet pose_set = PoseSet::kUniformWorkspace;
  int size = 0;
  ResidualForm formulation = ResidualForm::kCartesian;
  std::string solver;          // label
  PredictionError validation;  // against the truth, on fresh positions (mm)
  double floor_rms_mm = 0.0;   // Cramer-Rao floor of the RMS (0 without noise)
  int iterations = 0;          // LM iterations / Adam epochs / NLopt evaluations
  double time_s = 0.0;         // solver time
  std::string stop_reason;
  int seed = 0;  // 0: the simulation's own truth and draw
};

CompareSpec LoadCompareSpec(const std::string& path, Registry& registry);

// One row per (pose set, size, seed, formulation, solver), in that nesting order. With a
// `checkpoint` path, each finished (pose set, size, seed) is kept there and one found there is
// not run again (checkpoint.h).
std::vector<CompareRow> RunComparison(const CompareSpec& spec, Registry& registry,
                                      const std::string& checkpoint = "");

std::string CompareTableMarkdown(const CompareSpec& spec, const std::vector<CompareRow>& rows);
std::string CompareTableCsv(const std::vector<CompareRow>& rows);
// With more than one seed: one line per (pose set, size), which formulation and solver
// (solver_compare.h's Recommendation on the validation RMS).
std::vector<std::string> CompareRecommendations(const CompareSpec& spec,
                                                const std::vector<CompareRow>& rows);

}  // namespace cellmetry
