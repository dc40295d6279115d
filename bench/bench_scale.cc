// A factory's cell: how `cellmetry run` scales with robots, cameras and poses.
//
// The layout is configs/simulations/scale_10_ur3_8_cameras.yaml's at any size: UR3s in rows of
// five, 1 m apart, static cameras 2.5 m up, random joint poses, every camera seeing every tool
// and the world tag at every capture. Observations = robots x poses x cameras x 2.
//
//  BM_Run/R/C/P              the whole identification as `cellmetry run` without
//                            cross-validation and without leaving each camera out (the refits
//                            `run` adds: BM_Identify/exp_a_cameras_left_out): closed form, solve,
//                            identifiability, covariance,
//                            the cluster-robust and camera-jackknife sigma, residual statistics;
//                            each stage's seconds and peak MB as counters (<stage>_s, <stage>_MB)
//  BM_LargeCell/R/C/P        BM_Run on 1.28 and 2.56 million observations: the largest cells
//  BM_CrossValidation/R/C/P  5-fold cross-validation at the answer, on its own
//  BM_Solve, BM_Identifiability, BM_Covariance (10/8/500)   the stages, one by one
//  BM_RFactor/<method>       the factory cell's Jacobian reduced to its R factor: cellmetry's
//                            grouped QR (estimation/r_factor.h), SuiteSparseQR, and the dense
//                            Householder QR the covariance used before
//
// Every benchmark reports `peak_MB`: the process's peak resident memory during its iterations
// (the kernel's high-water mark, reset before each benchmark through /proc/self/clear_refs).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include <malloc.h>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_initial.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/estimation/estimation_quality.h"
#include "cellmetry/estimation/noise_model.h"
#include "bench_support.h"
#include "spqr_r_factor.h"

namespace cellmetry {
namespace {

struct CellSize {
  int robots, cameras, poses;
};

std::string SimulationYaml(const CellSize& size) {
  std::ostringstream yaml;
  yaml << "simulation: workcell\nseed: 15\nrepeats: 1\nrobots:\n";
  for (int r = 0; r < size.robots; ++r) {
    yaml << "  ur3_" << r << ":\n    model: " << bench::Source("configs/robots/ur3_vsb2020.yaml")
         << "\n"
         << "    base: {xyz: [" << 1000 * (r % 5) << ", " << 1200 * (r / 5) << ", 0], rvec: [0, 0, "
         << 0.3 * r << "]}\n"
         << "    tools: {tool_" << r << ": {xyz: [0.5, -0.3, 66]}}\n"
         << "    poses: {random: " << size.poses
         << ", lower: [-3.1, -2.8, -2.6, -3.1, -3.1, -3.1], upper: [3.1, -0.3, 2.6, 3.1, 3.1, "
            "3.1]}\n";
  }
  yaml << "cameras:\n";
  for (int c = 0; c < size.cameras; ++c) {
    yaml << "  cam" << c << ": {xyz: [" << -500 + 5000 * (c % 4) / 3 << ", "
         << -800 + 2800 * (c / 4) << ", 2500], rvec: [3.1, " << 0.05 * (c - 4) << ", 0]}\n";
  }
  yaml << "noise: {position_mm: [0.1, 0.1, 0.4], rotation_rad: [0.0005, 0.0005, 0.001]}\n";
  return yaml.str();
}

std::string JobYaml(const CellSize& size, const std::string& recording) {
  std::ostringstream yaml;
  yaml << "job: workcell\nrecording: " << recording << "\noutput: " << recording
       << "_result\ncamera_model: static_cameras\nrobots:\n";
  for (int r = 0; r < size.robots; ++r) {
    yaml << "  ur3_" << r << ":\n    model: " << bench::Source("configs/robots/ur3_vsb2020.yaml")
         << "\n    base: {free: all}\n    tools:\n      tool_" << r
         << ": {xyz: [0, 0, 66], free: [x, y, z]}\n";
  }
  yaml << "noise:\n  cameras:\n";
  for (int c = 0; c < size.cameras; ++c) {
    yaml << "    cam" << c
         << ": {position_mm: [0.1, 0.1, 0.4], rotation_rad: [0.0005, 0.0005, 0.001]}\n";
  }
  yaml << "solver: {type: ceres_lm}\nvalidation: {folds: 5}\n";
  return yaml.str();
}

void WriteText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

struct Cell {
  WorkcellJob job;
  Recording recording;
};

// The cell of `size`, simulated into a temporary folder.
Cell SimulateCell(const CellSize& size) {
  Registry& registry = bench::Plugins();
  char folder_template[] = "/tmp/cellmetry_bench_scale_XXXXXX";
  const std::string folder = mkdtemp(folder_template);
  WriteText(folder + "/simulation.yaml", SimulationYaml(size));
  const WorkcellSimulationSpec spec = LoadWorkcellSimulation(folder + "/simulation.yaml", registry);
  WorkcellTruth truth;
  WriteRecording(SimulateWorkcell(spec, &truth), folder + "/recording");
  WriteText(folder + "/job.yaml", JobYaml(size, folder + "/recording"));
  Cell cell;
  cell.job = LoadWorkcellJob(folder + "/job.yaml", registry);
  cell.recording = ReadRecording(folder + "/recording");
  std::system(("rm -rf '" + folder + "'").c_str());
  return cell;
}

// The cell of `size`, simulated when first asked for. Only the latest cell stays in memory, so a
// benchmark's peak_MB holds no other size's recording.
const Cell& CellOf(const CellSize& size) {
  static std::map<std::tuple<int, int, int>, Cell> cache;
  const auto key = std::make_tuple(size.robots, size.cameras, size.poses);
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  cache.clear();
  return cache.emplace(key, SimulateCell(size)).first->second;
}

SolverMaker CeresLm() {
  return [] {
    return bench::Plugins().CreateSolver("ceres_lm",
                                         ConfigNode::LoadString("type: ceres_lm", "bench"));
  };
}

// Peak resident memory: reset before a benchmark, read after it (PeakResidentMb, stage_clock.h).
// The allocator first hands freed pages back, or a small cell measured after a large one would
// carry the large one's heap.
void ResetPeakMemory() {
  malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
}

CellSize SizeOf(const benchmark::State& state) {
  return {static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
          static_cast<int>(state.range(2))};
}

void Count(benchmark::State& state, const CellSize& size) {
  state.counters["observations"] = 2.0 * size.robots * size.cameras * size.poses;
  state.counters["peak_MB"] = PeakResidentMb();
}

void BM_Run(benchmark::State& state) {
  const CellSize size = SizeOf(state);
  WorkcellProblem spec = CellOf(size).job.problem;
  spec.folds = 0;
  spec.leave_one_camera_out = false;  // the identification; the cameras left out are refits
  const Recording& recording = CellOf(size).recording;
  ResetPeakMemory();
  std::map<std::string, double> stage_s, stage_mb;
  for (auto _ : state) {
    const WorkcellResult result = IdentifyWorkcell(spec, recording, CeresLm());
    benchmark::DoNotOptimize(result.frames.front().pose.t.x());
    for (const StageTime& stage : result.stages) {
      stage_s[stage.stage] += stage.seconds / state.max_iterations;
      stage_mb[stage.stage] = std::max(stage_mb[stage.stage], stage.peak_resident_mb);
    }
  }
  Count(state, size);
  // Per stage: wall seconds and the peak resident memory at its end (it only grows).
  for (const auto& [stage, seconds] : stage_s) {
    state.counters[stage + "_s"] = seconds;
    state.counters[stage + "_MB"] = stage_mb[stage];
  }
}

void BM_CrossValidation(benchmark::State& state) {
  const CellSize size = SizeOf(state);
  const Cell& cell = CellOf(size);
  WorkcellProblem spec = cell.job.problem;
  spec.folds = 0;
  spec.leave_one_camera_out = false;
  const WorkcellResult answer = IdentifyWorkcell(spec, cell.recording, CeresLm());
  spec.folds = 5;
  const WorkcellData data = PrepareWorkcellData(spec, cell.recording);
  ResetPeakMemory();
  for (auto _ : state) {
    const HeldOut held_out =
        CrossValidate(spec, cell.recording, data, answer.noise, answer.estimate, {}, CeresLm());
    benchmark::DoNotOptimize(held_out.total.norm);
  }
  Count(state, size);
}

// The 10-robot cell's problem, assembled at the closed-form start and at the answer. It owns
// its cell and data: an assembled problem's residuals point into both.
struct Assembled {
  Cell cell;
  WorkcellData data;
  std::unique_ptr<AssembledWorkcell> at_start;
  std::unique_ptr<AssembledWorkcell> at_answer;
};
Assembled& FactoryCell() {
  static const std::unique_ptr<Assembled> assembled = [] {
    auto out = std::make_unique<Assembled>();
    out->cell = SimulateCell({10, 8, 500});
    const WorkcellProblem& spec = out->cell.job.problem;
    const Recording& recording = out->cell.recording;
    out->data = PrepareWorkcellData(spec, recording);
    const NoiseModel noise = BuildNoiseModel(recording, spec.noise);
    const WorkcellEstimate start = InitialEstimate(spec, recording, out->data);
    out->at_start = AssembleWorkcell(spec, recording, out->data, noise, start);
    out->at_answer = AssembleWorkcell(spec, recording, out->data, noise, start);
    CeresLm()()->Solve(out->at_answer->problem);
    return out;
  }();
  return *assembled;
}

void BM_Solve(benchmark::State& state) {
  Problem& problem = FactoryCell().at_start->problem;
  const Eigen::VectorXd start = problem.FreeValues();
  ResetPeakMemory();
  for (auto _ : state) {
    problem.SetFreeValues(start);
    const SolverSummary summary = CeresLm()()->Solve(problem);
    state.counters["iterations"] = summary.iterations;
  }
  // The next repetition solves from the start again, not from this answer (zero iterations).
  problem.SetFreeValues(start);
  Count(state, {10, 8, 500});
}

void BM_Linearize(benchmark::State& state) {
  Problem& problem = FactoryCell().at_answer->problem;
  ResetPeakMemory();
  for (auto _ : state) benchmark::DoNotOptimize(Linearize(problem).jacobian.nonZeros());
  Count(state, {10, 8, 500});
}

void BM_Identifiability(benchmark::State& state) {
  Problem& problem = FactoryCell().at_answer->problem;
  ResetPeakMemory();
  for (auto _ : state) benchmark::DoNotOptimize(FindUnidentifiable(problem, 1e-6).size());
  Count(state, {10, 8, 500});
}

void BM_Covariance(benchmark::State& state) {
  Problem& problem = FactoryCell().at_answer->problem;
  ResetPeakMemory();
  for (auto _ : state) benchmark::DoNotOptimize(ComputeUncertainty(problem).sigma[0]);
  Count(state, {10, 8, 500});
}

enum class RMethod { kGrouped, kSuiteSparse, kDense };

void BM_RFactor(benchmark::State& state, RMethod method) {
  Problem& problem = FactoryCell().at_answer->problem;
  SparseJacobian J;
  problem.EvaluateSparse(nullptr, &J);
  ResetPeakMemory();
  for (auto _ : state) {
    Eigen::MatrixXd R;
    if (method == RMethod::kGrouped) R = RFactor(J);
    if (method == RMethod::kSuiteSparse) R = bench::SuiteSparseRFactor(J);
    if (method == RMethod::kDense) {
      const Eigen::HouseholderQR<Eigen::MatrixXd> qr{Eigen::MatrixXd(J)};
      R = qr.matrixQR().topRows(J.cols()).triangularView<Eigen::Upper>();
    }
    benchmark::DoNotOptimize(R(0, 0));
  }
  Count(state, {10, 8, 500});
}
BENCHMARK_CAPTURE(BM_RFactor, grouped, RMethod::kGrouped)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RFactor, suitesparse, RMethod::kSuiteSparse)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_RFactor, dense, RMethod::kDense)->Unit(benchmark::kMillisecond)->Iterations(1);

// Robots, cameras, poses: from 1,000 to 160,000 observations.
void Sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"robots", "cameras", "poses"});
  b->Args({1, 2, 250});    //   1,000
  b->Args({2, 4, 250});    //   4,000
  b->Args({5, 4, 500});    //  20,000
  b->Args({10, 8, 500});   //  80,000: the factory cell
  b->Args({10, 8, 1000});  // 160,000
}

BENCHMARK(BM_Run)->Apply(Sizes)->Unit(benchmark::kMillisecond)->Iterations(1);
// The largest cells measured on this machine (docs/scale.md): run on their own, they take
// minutes and gigabytes (`--benchmark_filter=BM_LargeCell`).
BENCHMARK(BM_Run)
    ->Name("BM_LargeCell")
    ->ArgNames({"robots", "cameras", "poses"})
    ->Args({20, 16, 2000})  // 1,280,000
    ->Args({40, 16, 2000})  // 2,560,000
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK(BM_CrossValidation)->Apply(Sizes)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Solve)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Linearize)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Identifiability)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Covariance)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace cellmetry

BENCHMARK_MAIN();
