// White-dot and 13-dot pattern detector speed on rendered 1280 x 800 frames (OAK-D-like camera,
// noise sigma 2), time per frame on one core:
//
//  BM_Dot/detect          the `dot` plugin's Detect(): one 10 mm dot, 8 poses at 300..600 mm
//  BM_DotPattern/detect   the `dot_pattern` plugin's Detect(): the 13-dot diamond (6 mm dots,
//                         12 mm pitch), the same poses
// Target: BM_Dot/detect >= 200 frames/s (<= 5 ms per frame).
//   build/bin/bench_dot --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>

#include "cellmetry/basics/progress.h"
#include "cellmetry/imaging/render.h"
#include "cellmetry/registry/registry.h"
#include "bench_support.h"

namespace cellmetry {
namespace {

using bench::MakeDetector;

// Eight views of the detector's printed face, facing the camera, tilted up to 30 degrees.
std::vector<GrayImage> Frames(const Detector& d) {
  const std::vector<MarkerFace> faces = d.Faces(10.0);
  const PinholeCamera camera = OakDLikeCamera();
  std::mt19937 rng(42);
  std::vector<GrayImage> frames;
  for (int i = 0; i < 8; ++i) {
    const double tilt = (i % 4) * 10.0 * M_PI / 180;
    const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix() *
                              Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(i), std::sin(i), 0));
    const Eigen::Vector3d t(-90.0 + 25.0 * i, 40.0 - 11.0 * i, 300.0 + 300.0 * i / 7);
    frames.push_back(RenderView(camera, {{Pose{R, t}, &faces}}, RenderOptions(), rng));
  }
  return frames;
}

void BM_Detect(benchmark::State& state, const std::string& yaml) {
  const std::unique_ptr<Detector> detector = MakeDetector(yaml);
  const std::vector<GrayImage> frames = Frames(*detector);
  for (const auto& f : frames) {
    if (!detector->Detect(f.view()).found()) {
      state.SkipWithError("a rendered frame was not detected");
      return;
    }
  }
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(detector->Detect(frames[i++ % frames.size()].view()));
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(state.iterations(), benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(BM_Detect, dot, std::string("{type: dot}"))
    ->Name("BM_Dot/detect")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Detect, dot_pattern, std::string("{type: dot_pattern}"))
    ->Name("BM_DotPattern/detect")
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cellmetry

BENCHMARK_MAIN();
