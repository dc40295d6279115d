// The rendering simulator (imaging/render.h) on a 1280 x 800 OAK-D-like frame showing the
// 13-dot pattern at 400 mm, 4 x 4 rays per pixel: what the detector tests and the marker
// comparison pay per view.
//
//  BM_Render/ideal                 RenderIdeal, no lens distortion: each ray is the pixel's
//                                  normalised coordinates (PinholeCamera::Ray's shortcut)
//  BM_Render/ideal_newton          the same frame with k1 = 1e-12: every ray inverts the
//                                  distortion by Newton's method (the path the shortcut skips;
//                                  the image differs by far less than a gray level)
//  BM_Render/view                  RenderView: the ideal image plus the sensor, per view
//  BM_Render/sensor_only           SensorImage of an ideal image rendered once: a static
//                                  scene's further views, as the bias tests draw them
//   build/bin/bench_render --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>

#include "cellmetry/imaging/render.h"
#include "bench_support.h"

namespace cellmetry {
namespace {

struct Scene {
  std::vector<MarkerFace> faces;
  Pose T_cam_target;
};

const Scene& PatternAt400mm() {
  static const Scene scene = [] {
    const std::unique_ptr<Detector> detector = bench::MakeDetector("{type: dot_pattern}");
    const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    return Scene{detector->Faces(20.0), Pose{R, Eigen::Vector3d(12.5, 9.3, 400.0)}};
  }();
  return scene;
}

void BM_RenderIdeal(benchmark::State& state, double k1) {
  const Scene& scene = PatternAt400mm();
  PinholeCamera camera = OakDLikeCamera();
  camera.distortion[0] = k1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        RenderIdeal(camera, {{scene.T_cam_target, &scene.faces}}, RenderOptions()));
  }
}
BENCHMARK_CAPTURE(BM_RenderIdeal, ideal, 0.0)
    ->Name("BM_Render/ideal")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RenderIdeal, ideal_newton, 1e-12)
    ->Name("BM_Render/ideal_newton")
    ->Unit(benchmark::kMillisecond);

void BM_RenderView(benchmark::State& state) {
  const Scene& scene = PatternAt400mm();
  const PinholeCamera camera = OakDLikeCamera();
  std::mt19937 rng(1);
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        RenderView(camera, {{scene.T_cam_target, &scene.faces}}, RenderOptions(), rng));
  }
}
BENCHMARK(BM_RenderView)->Name("BM_Render/view")->Unit(benchmark::kMillisecond);

void BM_SensorOnly(benchmark::State& state) {
  const Scene& scene = PatternAt400mm();
  const PinholeCamera camera = OakDLikeCamera();
  const RenderOptions options;
  const std::vector<float> ideal =
      RenderIdeal(camera, {{scene.T_cam_target, &scene.faces}}, options);
  std::mt19937 rng(1);
  for (auto _ : state) {
    benchmark::DoNotOptimize(SensorImage(ideal, camera.width, camera.height, options, rng));
  }
}
BENCHMARK(BM_SensorOnly)->Name("BM_Render/sensor_only")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cellmetry

BENCHMARK_MAIN();
