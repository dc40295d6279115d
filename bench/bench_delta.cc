// Delta arm kinematic calibration speed: 125 simulated positions with the report's
// dot-detector noise, every geometric parameter and homing offset free, camera pose free.
//
//  BM_DeltaCalibrate/lm_forward      IdentifyWorkcell with ceres_lm, Cartesian residual
//                                    (closed-form camera, identifiability, covariance included)
//  BM_DeltaCalibrate/lm_inverse      the same, joint-space residual (two passes: re-weighting)
//  BM_DeltaCalibrate/adam_forward    gradient_descent (Adam) until its cost is within 1e-4 of
//                                    LM's minimum: the same answer (see the `val_rms_um` counter)
// The ratio adam_forward / lm_forward is the report's machine learning against LM; every case
// prints it as the counter x_lm_forward (against LM's median of 9 runs taken at start-up).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>

#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/prediction.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"

namespace cellmetry {
namespace {

struct Scenario {
  WorkcellSimulationSpec spec;
  WorkcellSimulationSpec truth;
  Recording recording;
  std::vector<std::vector<double>> validation;
  double lm_forward_cost = 0.0;  // LM's minimum, the target for Adam
  double lm_forward_s = 0.0;     // LM's time (median of 9), for Adam's ratio
};

// Only R - r is identifiable: hold r, as configs/jobs/delta_calibration.yaml does.
WorkcellProblem Problem(const Scenario& s, ResidualForm residual) {
  WorkcellProblem problem = SimulatedProblem(s.spec, residual);
  HoldModelParameters(".r", &problem);
  return problem;
}

SolverMaker Maker(const std::string& yaml) {
  return [yaml] {
    const ConfigNode config = ConfigNode::LoadString(yaml, "bench");
    return Registry::Global().CreateSolver(config["type"].AsString(), config);
  };
}

Scenario& Load() {
  static Scenario s = [] {
    Progress::SetQuiet(true);
    Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
    Scenario s;
    s.spec = LoadWorkcellSimulation(
        std::string(CELLMETRY_SOURCE_DIR) + "/configs/simulations/delta_uniform_125.yaml",
        Registry::Global());
    std::mt19937 rng(s.spec.seed);
    const SimulatedDraw draw = DrawAndSimulate(s.spec, rng);
    s.truth = draw.truth;
    s.recording = draw.recording;
    const WorkcellProblem problem = Problem(s, ResidualForm::kCartesian);
    s.validation = DrawPoseSet(PoseSetGeometryOf(s.spec, s.spec.robots.front(), ""),
                               PoseSet::kUniformWorkspace, 200, rng);
    std::vector<double> times;
    for (int i = 0; i < 9; ++i) {
      const auto start = std::chrono::steady_clock::now();
      s.lm_forward_cost =
          IdentifyWorkcell(problem, s.recording, Maker("type: ceres_lm")).solver.final_cost;
      times.push_back(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::nth_element(times.begin(), times.begin() + 4, times.end());
    s.lm_forward_s = times[4];
    return s;
  }();
  return s;
}

void BM_DeltaCalibrate(benchmark::State& state, ResidualForm residual, std::string solver) {
  Scenario& s = Load();
  if (solver == "adam") {
    solver = "{type: gradient_descent, learning_rate: 0.05, epochs: 200000, cost_tolerance: " +
             std::to_string(s.lm_forward_cost * (1 + 1e-4)) + "}";
  }
  const WorkcellProblem problem = Problem(s, residual);
  WorkcellResult result;
  double seconds = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    result = IdentifyWorkcell(problem, s.recording, Maker(solver));
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    benchmark::DoNotOptimize(result.estimate.model.at("delta").data());
  }
  state.counters["x_lm_forward"] = seconds / s.lm_forward_s;  // time ratio to LM, last iteration
  state.counters["iterations"] = result.solver.iterations;
  state.counters["val_rms_um"] =
      1e3 * ComparePredictions(*s.spec.robots.front().model, result.estimate,
                               TruthEstimate(s.truth), {"delta", "marker", "stereo"}, s.validation)
                .rms_mm;
}

BENCHMARK_CAPTURE(BM_DeltaCalibrate, lm_forward, ResidualForm::kCartesian,
                  std::string("type: ceres_lm"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DeltaCalibrate, lm_inverse, ResidualForm::kJointSpace,
                  std::string("type: ceres_lm"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DeltaCalibrate, adam_forward, ResidualForm::kCartesian, std::string("adam"))
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace cellmetry

BENCHMARK_MAIN();
