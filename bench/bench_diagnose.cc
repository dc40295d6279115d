// The physics finder's speed: a full diagnosis (geometry, every candidate of the library scored,
// refits, 10-fold cross-validation, 40 bootstrap resamples) of a 250-pose UR3 recording with one
// concealed effect. Target: under 2 s on this machine (issue 15; 7 s before it).
//   BM_Diagnose250Poses/rivals      the finder as jobs run it (the rival test as its gate)
//   BM_Diagnose250Poses/bootstrap   the same with the gate it replaced (selection_test: bootstrap)
#include <benchmark/benchmark.h>

#include <random>
#include <string>

#include "bench_support.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/cell/workcell_simulation.h"

namespace cellmetry {
namespace {

void BM_Diagnose250Poses(benchmark::State& state, const std::string& selection_test) {
  Registry& registry = bench::Plugins();
  WorkcellSimulationSpec spec =
      LoadWorkcellSimulation(bench::Source("configs/simulations/ur3_physics_base.yaml"), registry);
  spec.robots[0].joint_poses.clear();
  std::mt19937 rng(3);
  // The proof cell's ranges (configs/simulations/ur3_physics_base.yaml), 250 poses.
  const std::vector<double> lower = {-6.2, 2.4, -2.2, -6.2, -6.2, -6.2},
                            upper = {6.2, 4.2, 2.2, 6.2, 6.2, 6.2};
  for (int i = 0; i < 250; ++i) {
    std::vector<double> q(6);
    for (int j = 0; j < 6; ++j)
      q[j] = std::uniform_real_distribution<double>(lower[j], upper[j])(rng);
    spec.robots[0].joint_poses.push_back(q);
  }
  SimulatedEffect compliance;
  compliance.name = "ur3.joint_compliance";
  compliance.effect = registry.CreateEffect(
      "joint_compliance",
      ConfigNode::LoadString("{type: joint_compliance, joints: [2], "
                             "link_masses_kg: [2.0, 3.42, 1.26, 0.8, 0.8, 0.35]}", "bench"),
      *spec.robots[0].model);
  compliance.values = {1e-5};
  spec.robots[0].effects.push_back(compliance);
  const Recording recording = SimulateWorkcell(spec, nullptr);
  DiagnosisJob job =
      LoadDiagnosisJob(bench::Source("configs/jobs/ur3_diagnose.yaml"), registry, false);
  job.options.selection_test = selection_test;
  const SolverMaker make_solver = [&] {
    return registry.CreateSolver(job.workcell.solver_type, *job.workcell.solver_config);
  };
  const auto candidates = JobCandidates(job, recording, registry);
  int accepted = 0;
  for (auto _ : state) {
    const DiagnosisResult d = DiagnoseWorkcell(job.workcell.problem, recording, make_solver,
                                               candidates, job.options, "bench");
    accepted = static_cast<int>(d.accepted.size());
  }
  state.counters["candidates"] = static_cast<double>(candidates.size());
  state.counters["effects_found"] = accepted;
}
BENCHMARK_CAPTURE(BM_Diagnose250Poses, rivals, std::string("rivals"))
    ->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_Diagnose250Poses, bootstrap, std::string("bootstrap"))
    ->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(true);

}  // namespace
}  // namespace cellmetry

BENCHMARK_MAIN();
