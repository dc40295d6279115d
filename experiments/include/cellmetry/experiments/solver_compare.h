// `compare: solvers`: solvers x camera models (static_cameras / per_frame) on a serial workcell,
// every row repeated over seeds, reported as a mean with a 95 % t-interval, the solvers' stop
// reasons and iterations, and one recommendation line per question ("which solver, with static
// cameras?"; "which camera model, with ceres_lm?"), ties called ties (overlapping intervals).
//
// Compare spec (YAML, `compare: solvers`):
//   job: <job file>                      # the problem fitted (robots, tools, what is free)
//   simulation: <simulation spec>        # optional: a fresh recording per seed (noise seed
//                                        # varies); scored by the bases' position error against
//                                        # the truth. Without it: the job's own recording,
//                                        # scored by held-out RMS (k-fold by pose; the seed
//                                        # varies the fold assignment), as there is no truth
//   solvers: {<label>: <solver block>, ...}
//   camera_models: [static_cameras, per_frame]   # default: both
//   seeds: 10                            # repetitions per row (default 10)
//   output: <folder for table.md and table.csv>
// The job's uncertain_inputs are dropped: they widen sigma and never move the answer, and the
// comparison scores answers.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/experiments/intervals.h"

namespace cellmetry {

// A solver's stop reason as words to count over seeds: its first clause, up to ". " or ";",
// without the measured figures that differ per run ("Parameter tolerance reached" from
// "Parameter tolerance reached. Relative step_norm: 5.8e-13 <= 1e-12."; "5000 epochs done
// (limit)" from "5000 epochs done (limit); kept epoch 4994, the lowest cost"; "predicted cost
// decrease below the tolerance" from "predicted cost decrease 2.2e-12 below the tolerance").
std::string StopReasonWords(const std::string& reason);

// One candidate answer to a question: per-seed error (lower is better) and solve time.
struct Contender {
  std::string label;
  std::vector<double> error;
  std::vector<double> time_s;
};

// One line: "<question>: <label>: ..." — the most accurate one when no other has the same
// accuracy (SameScore); among those of the same accuracy, the fastest when no other has the same
// time ("A: same accuracy as B at 1/4 the time"); otherwise "tie: A, B (same accuracy, ... and
// same time)"; then the slower and the less accurate ones.
// `error_resolution` (in the error's unit) and `time_resolution_s`: SameScore's resolutions.
std::string Recommendation(const std::string& question, const std::vector<Contender>& contenders,
                           const std::string& unit, double error_resolution = 1e-6,
                           double time_resolution_s = 1e-4);

struct SolverCompareSpec {
  std::string file;
  std::string description;
  WorkcellJob job;
  std::optional<WorkcellSimulationSpec> simulation;         // none: the job's recording, no truth
  std::vector<std::pair<std::string, ConfigNode>> solvers;  // label, solver block
  std::vector<CameraModel> camera_models;
  int seeds = 10;
  std::string output;
};

struct SolverCompareRow {
  CameraModel camera_model = CameraModel::kStaticCameras;
  std::string solver;            // label
  std::vector<double> error_mm;  // per seed: truth error or held-out RMS
  std::vector<double> time_s;    // per seed: solver time
  std::vector<int> iterations;
  int converged = 0;                        // seeds whose solver stopped on a convergence test
  std::map<std::string, int> stop_reasons;  // the reason's words (numbers cut), count
};

SolverCompareSpec LoadSolverCompare(const std::string& path, Registry& registry);
// One row per (camera model, solver), in that nesting order. With a `checkpoint` path, each
// finished seed is kept there and a seed found there is not run again (checkpoint.h).
std::vector<SolverCompareRow> RunSolverCompare(const SolverCompareSpec& spec, Registry& registry,
                                               const std::string& checkpoint = "");
// One line per question: each camera model's solvers; each solver's camera models.
std::vector<std::string> SolverCompareRecommendations(const SolverCompareSpec& spec,
                                                      const std::vector<SolverCompareRow>& rows);
std::string SolverCompareMarkdown(const SolverCompareSpec& spec,
                                  const std::vector<SolverCompareRow>& rows);
std::string SolverCompareCsv(const std::vector<SolverCompareRow>& rows);

}  // namespace cellmetry
