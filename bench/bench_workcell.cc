// Workcell identification speed on the VSB recordings.
//
//  BM_Identify/sim_b   closed form + ceres_lm fit(s) + covariance, as `cellmetry run` without
//                      cross-validation (target: <= 5 ms); counters ms_<stage>
//  BM_Identify/exp_a   2,500 captures, 3 cameras, 7,500 tool observations, static cameras
//                      (target: <= 60 ms)
//  BM_Identify/exp_a_cameras_left_out   exp_a's best model (vsb_exp_a.yaml) as `cellmetry run`
//                      runs it, each camera left out (its stage: ms_cameras_left_out), against
//                      BM_Identify/exp_a_best, the same without
//  BM_Identify/<case>_plain_outlier_test   the same, outliers tested on the plain fit only
//                      (`outliers: plain`): the robust first fit's cost is the difference
//  BM_Solve/<solver>   the same assembled sim_b problem from the closed-form start, each solver
//  BM_Solve/exp_a_<solver>   exp_a's assembled problem from the closed-form start
//  BM_PrepareData/exp_a, BM_Repeatability/exp_a, BM_ClosedFormStart/exp_a, BM_Assemble/exp_a
//                      an identification's first stages alone; BM_NormalEquations,
//                      BM_SparseJacobian, BM_RFactor: one evaluation of exp_a's problem
#include <benchmark/benchmark.h>

#include <map>
#include <string>

#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_initial.h"
#include "cellmetry/estimation/noise_model.h"

namespace cellmetry {
namespace {

struct Loaded {
  WorkcellJob job;
  Recording recording;
};

const Loaded& Load(const std::string& job_file) {
  static std::map<std::string, Loaded> cache;
  auto it = cache.find(job_file);
  if (it == cache.end()) {
    Progress::SetQuiet(true);
    Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
    Loaded loaded;
    loaded.job =
        LoadWorkcellJob(std::string(CELLMETRY_SOURCE_DIR) + "/" + job_file, Registry::Global());
    loaded.job.problem.folds = 0;
    loaded.job.problem.compare_camera_models = false;
    loaded.recording = ReadRecording(loaded.job.recording);
    it = cache.emplace(job_file, std::move(loaded)).first;
  }
  return it->second;
}

void BM_Identify(benchmark::State& state, const std::string& job_file,
                 OutlierTest outlier_test = OutlierTest::kRobust,
                 const std::string& solver_type = "ceres_lm", bool cameras_left_out = false) {
  const Loaded& loaded = Load(job_file);
  const ConfigNode solver = ConfigNode::LoadString("type: " + solver_type, "bench");
  WorkcellProblem problem = loaded.job.problem;
  problem.outlier_test = outlier_test;
  problem.leave_one_camera_out = cameras_left_out;
  // Where the time goes: each stage's wall milliseconds per identification, as counters
  // (`ms_<stage>`; the stages of workcell.cc's StageClock).
  std::map<std::string, double> stage_ms;
  for (auto _ : state) {
    const WorkcellResult result = IdentifyWorkcell(problem, loaded.recording, [&] {
      return Registry::Global().CreateSolver(solver_type, solver);
    });
    benchmark::DoNotOptimize(result.frames.front().pose.t.x());
    for (const StageTime& stage : result.stages) stage_ms[stage.stage] += 1e3 * stage.seconds;
  }
  for (const auto& [stage, ms] : stage_ms) {
    state.counters["ms_" + stage] = benchmark::Counter(ms, benchmark::Counter::kAvgIterations);
  }
}
BENCHMARK_CAPTURE(BM_Identify, sim_b, std::string("configs/jobs/vsb_sim_b.yaml"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Identify, exp_a, std::string("configs/jobs/vsb_exp_a_geometry.yaml"))
    ->Unit(benchmark::kMillisecond);
// The best model as `cellmetry run` runs it: each of the three cameras left out and refitted.
BENCHMARK_CAPTURE(BM_Identify, exp_a_best, std::string("configs/jobs/vsb_exp_a.yaml"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Identify, exp_a_cameras_left_out, std::string("configs/jobs/vsb_exp_a.yaml"),
                  OutlierTest::kRobust, std::string("ceres_lm"), true)
    ->Unit(benchmark::kMillisecond);

// The same with the outlier test on the plain fit only (outliers: plain): what the robust first
// fit costs (outliers.h).
BENCHMARK_CAPTURE(BM_Identify, sim_b_plain_outlier_test, std::string("configs/jobs/vsb_sim_b.yaml"),
                  OutlierTest::kPlain)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Identify, exp_a_plain_outlier_test,
                  std::string("configs/jobs/vsb_exp_a_geometry.yaml"), OutlierTest::kPlain)
    ->Unit(benchmark::kMillisecond);

// The same with the normal_lm solver (Levenberg-Marquardt on normal equations summed per block).
BENCHMARK_CAPTURE(BM_Identify, sim_b_normal_lm, std::string("configs/jobs/vsb_sim_b.yaml"),
                  OutlierTest::kRobust, std::string("normal_lm"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Identify, exp_a_normal_lm, std::string("configs/jobs/vsb_exp_a_geometry.yaml"),
                  OutlierTest::kRobust, std::string("normal_lm"))
    ->Unit(benchmark::kMillisecond);

// One evaluation of exp_a's assembled problem at the closed-form start: the normal equations
// summed per block (what normal_lm and the robust fit iterate on) against the sparse Jacobian
// (what identifiability and the covariance linearize).
struct AssembledCase {
  WorkcellData data;
  NoiseModel noise;
  std::unique_ptr<AssembledWorkcell> assembled;
};
const AssembledCase& ExpAAssembled() {
  static AssembledCase c = [] {
    const Loaded& loaded = Load("configs/jobs/vsb_exp_a_geometry.yaml");
    AssembledCase out;
    out.data = PrepareWorkcellData(loaded.job.problem, loaded.recording);
    out.noise = BuildNoiseModel(loaded.recording, loaded.job.problem.noise);
    const WorkcellEstimate start = InitialEstimate(loaded.job.problem, loaded.recording, out.data);
    out.assembled =
        AssembleWorkcell(loaded.job.problem, loaded.recording, out.data, out.noise, start);
    return out;
  }();
  return c;
}
// exp_a's observations paired with its robot and cameras (PrepareWorkcellData), and the closed-
// form start from them (InitialEstimate): the first two stages of every identification.
void BM_PrepareData(benchmark::State& state) {
  const Loaded& loaded = Load("configs/jobs/vsb_exp_a_geometry.yaml");
  for (auto _ : state) {
    const WorkcellData data = PrepareWorkcellData(loaded.job.problem, loaded.recording);
    benchmark::DoNotOptimize(data.tools.size());
  }
}
BENCHMARK(BM_PrepareData)->Name("BM_PrepareData/exp_a")->Unit(benchmark::kMillisecond);
// The spread of exp_a's repeated captures (EstimateRepeatability), found beside the pairing on
// the other core.
void BM_Repeatability(benchmark::State& state) {
  const Loaded& loaded = Load("configs/jobs/vsb_exp_a_geometry.yaml");
  for (auto _ : state) {
    const NoiseModel spread = EstimateRepeatability(loaded.recording);
    benchmark::DoNotOptimize(spread.entries.size());
  }
}
BENCHMARK(BM_Repeatability)->Name("BM_Repeatability/exp_a")->Unit(benchmark::kMillisecond);
void BM_ClosedFormStart(benchmark::State& state) {
  const Loaded& loaded = Load("configs/jobs/vsb_exp_a_geometry.yaml");
  const WorkcellData data = PrepareWorkcellData(loaded.job.problem, loaded.recording);
  for (auto _ : state) {
    const WorkcellEstimate start = InitialEstimate(loaded.job.problem, loaded.recording, data);
    benchmark::DoNotOptimize(start.T_world_base.size());
  }
}
BENCHMARK(BM_ClosedFormStart)->Name("BM_ClosedFormStart/exp_a")->Unit(benchmark::kMillisecond);
// exp_a's problem assembled (and built) at the closed-form start and let go: what every fit, each
// cross-validation fold and the uncertain inputs' link pay before they evaluate anything.
void BM_Assemble(benchmark::State& state) {
  const AssembledCase& c = ExpAAssembled();
  const Loaded& loaded = Load("configs/jobs/vsb_exp_a_geometry.yaml");
  const WorkcellEstimate start = InitialEstimate(loaded.job.problem, loaded.recording, c.data);
  for (auto _ : state) {
    const auto assembled =
        AssembleWorkcell(loaded.job.problem, loaded.recording, c.data, c.noise, start);
    benchmark::DoNotOptimize(assembled->problem.num_free());
  }
}
BENCHMARK(BM_Assemble)->Name("BM_Assemble/exp_a")->Unit(benchmark::kMillisecond);
void BM_NormalEquations(benchmark::State& state) {
  const Problem& problem = ExpAAssembled().assembled->problem;
  NormalEquations at;
  for (auto _ : state) benchmark::DoNotOptimize(problem.EvaluateNormalEquations(&at));
  state.counters["blocks"] = static_cast<double>(problem.residual_infos().size());
  state.counters["free"] = problem.num_free();
}
BENCHMARK(BM_NormalEquations)->Name("BM_NormalEquations/exp_a")->Unit(benchmark::kMillisecond);
void BM_SparseJacobian(benchmark::State& state) {
  const Problem& problem = ExpAAssembled().assembled->problem;
  Eigen::VectorXd r;
  SparseJacobian J;
  for (auto _ : state) benchmark::DoNotOptimize(problem.EvaluateSparse(&r, &J));
}
BENCHMARK(BM_SparseJacobian)->Name("BM_SparseJacobian/exp_a")->Unit(benchmark::kMillisecond);
// That Jacobian reduced to its R factor (what identifiability and the covariance factor).
void BM_RFactor(benchmark::State& state) {
  const Problem& problem = ExpAAssembled().assembled->problem;
  Eigen::VectorXd r;
  SparseJacobian J;
  problem.EvaluateSparse(&r, &J);
  for (auto _ : state) benchmark::DoNotOptimize(RFactor(J).data());
}
BENCHMARK(BM_RFactor)->Name("BM_RFactor/exp_a")->Unit(benchmark::kMillisecond);

const std::string kSimB = "configs/jobs/vsb_sim_b.yaml";
// exp_a's 22,500 blocks in 1,506 units sharing a prediction: the step of BM_Identify/exp_a that
// is the job's solver.
const std::string kExpA = "configs/jobs/vsb_exp_a_geometry.yaml";

// A job's recording prepared, its noise and the closed-form start, what every solve starts from.
struct SolveCase {
  WorkcellData data;
  NoiseModel noise;
  WorkcellEstimate start;
};
const SolveCase& SolveCaseOf(const std::string& job_file) {
  static std::map<std::string, SolveCase> cache;
  auto it = cache.find(job_file);
  if (it != cache.end()) return it->second;
  const Loaded& loaded = Load(job_file);
  const WorkcellProblem& spec = loaded.job.problem;
  SolveCase c;
  c.data = PrepareWorkcellData(spec, loaded.recording);
  NoiseSpec noise_spec = spec.noise;
  if (job_file == kSimB) {  // no repeated captures to measure sigma: its residual RMS
    noise_spec.position_sigma_mm["cam1"] = Eigen::Vector3d(0.56, 0.52, 0.31);
  }
  c.noise = BuildNoiseModel(loaded.recording, noise_spec);
  c.start = InitialEstimate(spec, loaded.recording, c.data);
  return cache.emplace(job_file, std::move(c)).first->second;
}

void BM_Solve(benchmark::State& state, const std::string& job_file,
              const std::string& solver_yaml) {
  const Loaded& loaded = Load(job_file);
  const SolveCase& c = SolveCaseOf(job_file);
  const ConfigNode config = ConfigNode::LoadString(solver_yaml, "bench");
  int iterations = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto assembled =
        AssembleWorkcell(loaded.job.problem, loaded.recording, c.data, c.noise, c.start);
    auto solver = Registry::Global().CreateSolver(config["type"].AsString(), config);
    state.ResumeTiming();
    iterations = solver->Solve(assembled->problem).iterations;
  }
  state.counters["iterations"] = iterations;
}
const std::string kDenseCeres = "{type: ceres_lm, linear_solver: dense_normal_cholesky}";
BENCHMARK_CAPTURE(BM_Solve, ceres_lm, kSimB, std::string("type: ceres_lm"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Solve, ceres_lm_dense_normal_cholesky, kSimB, kDenseCeres)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Solve, normal_lm, kSimB, std::string("type: normal_lm"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Solve, jacobian_pinv, kSimB, std::string("type: jacobian_pinv"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Solve, nlopt_LD_LBFGS, kSimB,
                  std::string("{type: nlopt, algorithm: LD_LBFGS}"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Solve, nlopt_LN_BOBYQA, kSimB,
                  std::string("{type: nlopt, algorithm: LN_BOBYQA}"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Solve, gradient_descent, kSimB,
                  std::string("{type: gradient_descent, learning_rate: 0.1, epochs: 5000, "
                              "gradient_tolerance: 1e-8}"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Solve, exp_a_ceres_lm, kExpA, std::string("type: ceres_lm"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Solve, exp_a_ceres_lm_dense_normal_cholesky, kExpA, kDenseCeres)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Solve, exp_a_normal_lm, kExpA, std::string("type: normal_lm"))
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cellmetry

BENCHMARK_MAIN();
