// The physics finder's speed: a full diagnosis (geometry, every candidate of the library scored,
// refits, 10-fold cross-validation, 40 bootstrap resamples) of a 250-pose, two-camera UR3
// recording with one concealed effect (joint 2 compliance), and of experiment A's real recording.
// Targets on this machine: 250 poses with every model parameter free within 5 s; experiment A
// within 15 s.
//   BM_Diagnose250Poses/rivals          the finder as jobs run it (the rival test as its gate)
//   BM_Diagnose250Poses/bootstrap       the same with the gate it replaced (selection_test:
//                                       bootstrap)
//   BM_Diagnose250Poses/every_mdh_free  `rivals` with every MDH entry of the UR3 free
//                                       (`free_model: all`)
//   BM_DiagnoseExpA                     `cellmetry diagnose configs/jobs/vsb_exp_a_diagnose.yaml`
//                                       (three cameras, 250 poses x 10 captures)
//   BM_PlanExpA                         `cellmetry plan` on the same job: the pose choice after
//                                       the identification (which is left out of the time)
#include <benchmark/benchmark.h>

#include <random>
#include <string>

#include "cellmetry/cell/camera_left_out.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/diagnosis/pose_plan.h"
#include "bench_support.h"

namespace cellmetry {
namespace {

// Times DiagnoseWorkcell on `job` and `recording` as `cellmetry diagnose` runs it.
void TimeDiagnosis(benchmark::State& state, const DiagnosisJob& job, const Recording& recording) {
  Registry& registry = bench::Plugins();
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

// `every_mdh_free`: the UR3's model parameters all identified with the geometry.
void BM_Diagnose250Poses(benchmark::State& state, const std::string& selection_test,
                         bool every_mdh_free) {
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
                             "link_masses_kg: [2.0, 3.42, 1.26, 0.8, 0.8, 0.35]}",
                             "bench"),
      *spec.robots[0].model);
  compliance.values = {1e-5};
  spec.robots[0].effects.push_back(compliance);
  const Recording recording = SimulateWorkcell(spec, nullptr);
  DiagnosisJob job =
      LoadDiagnosisJob(bench::Source("configs/jobs/ur3_diagnose.yaml"), registry, false);
  job.options.selection_test = selection_test;
  if (every_mdh_free) {  // the job's `free_model: all`
    for (auto& robot : job.workcell.problem.robots) {
      for (auto& p : robot.model_parameters) p.fixed = false;
    }
  }
  TimeDiagnosis(state, job, recording);
}
BENCHMARK_CAPTURE(BM_Diagnose250Poses, rivals, std::string("rivals"), false)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_Diagnose250Poses, bootstrap, std::string("bootstrap"), false)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK_CAPTURE(BM_Diagnose250Poses, every_mdh_free, std::string("rivals"), true)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

// Experiment A's recording, read and stripped of unused cameras as cmd_diagnose.cc does.
Recording ExpARecording(const DiagnosisJob& job) {
  const Recording read = ReadRecording(job.workcell.recording);
  ValidateJobAgainstRecording(job.workcell, read);
  return WithoutCameras(read, UnusedCameras(job.workcell.problem));
}

void BM_DiagnoseExpA(benchmark::State& state) {
  Registry& registry = bench::Plugins();
  const DiagnosisJob job =
      LoadDiagnosisJob(bench::Source("configs/jobs/vsb_exp_a_diagnose.yaml"), registry);
  TimeDiagnosis(state, job, ExpARecording(job));
}
BENCHMARK(BM_DiagnoseExpA)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

// PlanPoses as cmd_plan.cc calls it: every candidate the recorded poses leave untestable, the
// default pose count and draws; the identification it starts from made once, outside the time.
void BM_PlanExpA(benchmark::State& state) {
  Registry& registry = bench::Plugins();
  const DiagnosisJob job =
      LoadDiagnosisJob(bench::Source("configs/jobs/vsb_exp_a_diagnose.yaml"), registry);
  const Recording recording = ExpARecording(job);
  const SolverMaker make_solver = [&] {
    return registry.CreateSolver(job.workcell.solver_type, *job.workcell.solver_config);
  };
  const auto candidates = JobCandidates(job, recording, registry);
  WorkcellProblem problem = job.workcell.problem;
  problem.folds = 0;
  problem.leave_one_camera_out = false;
  const WorkcellResult fitted = IdentifyWorkcell(problem, recording, make_solver);
  const PosePlanOptions options;
  int chosen = 0;
  for (auto _ : state) {
    const PosePlan plan = PlanPoses(problem, recording, fitted, candidates, options);
    chosen = static_cast<int>(plan.poses.size());
  }
  state.counters["poses"] = chosen;
}
BENCHMARK(BM_PlanExpA)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

}  // namespace
}  // namespace cellmetry

BENCHMARK_MAIN();
