// `cellmetry detect` throughput: 2,000 rendered 1280x800 frames of the white dot (1,000
// stereo samples of the delta arm), detected with one thread and with every core. The ratio of
// the two is how well detect uses the machine (2 cores here: ideally 2x).
//
//  BM_Detect/threads:1, BM_Detect/threads:2   frames/s in the `frames_per_s` counter
#include <benchmark/benchmark.h>

#include <filesystem>

#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/imaging/detection.h"
#include "cellmetry/imaging/image_simulation.h"

namespace cellmetry {
namespace {

constexpr int kSamples = 1000;  // x 2 views

// Renders the recording once per process into a temporary folder.
const std::string& Recording2000() {
  static const std::string folder = [] {
    Progress::SetQuiet(true);
    Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
    const std::string dir =
        (std::filesystem::temp_directory_path() / "cellmetry_bench_detect").string();
    WorkcellSimulationSpec spec = LoadWorkcellSimulation(
        std::string(CELLMETRY_SOURCE_DIR) + "/configs/simulations/delta_images.yaml",
        Registry::Global());
    spec.robots.front().pose_set = PoseSetSpec{PoseSet::kCameraView, kSamples, ""};
    std::mt19937 rng(1);
    const SimulatedDraw draw = DrawAndSimulate(spec, rng);
    Recording recording = draw.recording;
    recording.observations.clear();
    const std::vector<SampleView> views = WorkcellViews(draw.truth, recording);
    const auto write = PlanImages(
        ReadImageRenderSpec(*spec.images, CameraNames(spec), TargetNames(spec), Registry::Global()),
        views, 1, Registry::Global(), &recording);
    WriteRecording(recording, dir, "", write);
    return dir;
  }();
  return folder;
}

void BM_Detect(benchmark::State& state) {
  DetectJob job;
  job.recording = Recording2000();
  job.targets = {ReadTargetMarker("marker",
                                  ConfigNode::LoadString("{type: dot, diameter_mm: 10}", "bench"),
                                  Registry::Global())};
  job.cameras["stereo"].rig = OakDLikeRig();
  job.threads = static_cast<int>(state.range(0));
  int frames = 0;
  for (auto _ : state) {
    state.PauseTiming();
    std::filesystem::remove(job.recording + "/detections.jsonl");
    state.ResumeTiming();
    frames = RunDetection(job, Registry::Global()).processed;
  }
  state.counters["frames"] = frames;
  state.counters["frames_per_s"] =
      benchmark::Counter(frames, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Detect)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

}  // namespace
}  // namespace cellmetry

BENCHMARK_MAIN();
