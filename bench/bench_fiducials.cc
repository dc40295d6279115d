// Square-fiducial detector speed: each plugin against calling its library directly on the same
// rendered 1280 x 800 frames (8 poses, 350..600 mm, noise sigma 2), with the same settings.
//
//  BM_aruco/plugin             the `aruco` plugin's Detect(): DICT_6X6_250 5 x 4 grid board
//  BM_aruco/direct             cv::aruco::detectMarkers with the plugin's parameters
//                              (CORNER_REFINE_SUBPIX, window 5, 50 iterations, 0.01 px)
//  BM_apriltag_board/plugin    the `apriltag_board` plugin's Detect(): tag36h11 5 x 4 grid
//  BM_apriltag_board/direct    apriltag_detector_detect with the plugin's settings
//                              (decimate 2, sigma 0, min_white_black_diff 20, refine edges,
//                              sharpening 0.25, 1 thread, 1 bit corrected)
//  BM_apriltag_board/plugin_full_resolution, /direct_full_resolution   quad_decimate 1 and
//                              min_white_black_diff 5 (the plugin's earlier defaults)
//  BM_apriltag_board/plugin_min_white_black_diff_5, /direct_...   decimate 2, the library's 5
//  BM_apriltag_board/plugin_no_refine_edges, /direct_no_refine_edges   decimate 2 without the
//                              library's refine_edges (the plugin's edge lines alone)
//  BM_<plugin>/plugin_library_corners   the plugin without its edge refinement (edge_lines.h):
//                              the wrapper alone
// The target: plugin within 5 % of direct. Time is per frame. OpenCV's thread pool is
// off (cv::setNumThreads(1)) for every case: the core runs one detector per thread, and on a
// shared machine the pool's threads only add noise to a comparison of single calls.
//   build/bin/bench_fiducials --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <apriltag.h>
#include <tag36h11.h>

#include <opencv2/aruco.hpp>

#include <random>

#include "cellmetry/basics/progress.h"
#include "cellmetry/imaging/render.h"
#include "cellmetry/registry/registry.h"
#include "bench_support.h"

namespace cellmetry {
namespace {

constexpr char kAruco[] =
    "{type: aruco, dictionary: DICT_6X6_250, marker_length_mm: 30, markers_x: 5, markers_y: 4, "
    "separation_mm: 7.5}";
constexpr char kAprilTag[] =
    "{type: apriltag_board, family: tag36h11, tags_x: 5, tags_y: 4, tag_size_mm: 30, "
    "spacing_mm: 9}";
// The same without the plugin's edge refinement: the library's corners, as direct gives them.
constexpr char kArucoLibraryCorners[] =
    "{type: aruco, dictionary: DICT_6X6_250, marker_length_mm: 30, markers_x: 5, markers_y: 4, "
    "separation_mm: 7.5, edge_refinement: false}";
constexpr char kAprilTagFullResolution[] =
    "{type: apriltag_board, family: tag36h11, tags_x: 5, tags_y: 4, tag_size_mm: 30, "
    "spacing_mm: 9, quad_decimate: 1, min_white_black_diff: 5}";
constexpr char kAprilTagNoRefineEdges[] =
    "{type: apriltag_board, family: tag36h11, tags_x: 5, tags_y: 4, tag_size_mm: 30, "
    "spacing_mm: 9, refine_edges: false}";
constexpr char kAprilTagWhiteBlack5[] =
    "{type: apriltag_board, family: tag36h11, tags_x: 5, tags_y: 4, tag_size_mm: 30, "
    "spacing_mm: 9, min_white_black_diff: 5}";
constexpr char kAprilTagLibraryCorners[] =
    "{type: apriltag_board, family: tag36h11, tags_x: 5, tags_y: 4, tag_size_mm: 30, "
    "spacing_mm: 9, edge_refinement: false}";

// OpenCV's own threads off: plugin and library are compared on one core each.
std::unique_ptr<Detector> Make(const std::string& yaml) {
  cv::setNumThreads(1);
  return bench::MakeDetector(yaml);
}

// Eight views of the detector's printed faces, facing the camera (z of the face toward it).
std::vector<GrayImage> Frames(const Detector& d) {
  const std::vector<MarkerFace> faces = d.Faces(8.0);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : d.layout()) centre += p.p_target_mm;
  centre /= static_cast<double>(d.layout().size());
  std::mt19937 rng(7);
  std::vector<GrayImage> frames;
  for (int i = 0; i < 8; ++i) {
    const double tilt = 0.35 * std::sin(1.3 * i);
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(i), std::sin(i), 0)).toRotationMatrix() *
        Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix() *
        faces[0].T_target_face.R.transpose();
    const Eigen::Vector3d at(30.0 * std::cos(2.1 * i), 20.0 * std::sin(1.7 * i), 350.0 + 35.0 * i);
    const Pose T_cam_target{R, at - R * centre};
    frames.push_back(RenderView(OakDLikeCamera(), {{T_cam_target, &faces}}, RenderOptions(), rng));
  }
  return frames;
}

void BM_Plugin(benchmark::State& state, const char* yaml) {
  const auto detector = Make(yaml);
  const std::vector<GrayImage> frames = Frames(*detector);
  size_t i = 0, keypoints = 0;
  for (auto _ : state) {
    const Detection detection = detector->Detect(frames[i++ % frames.size()].view());
    keypoints += detection.keypoints.size();
    benchmark::DoNotOptimize(detection);
  }
  state.counters["keypoints"] =
      benchmark::Counter(static_cast<double>(keypoints) / state.iterations());
}

void BM_ArucoDirect(benchmark::State& state) {
  const std::vector<GrayImage> frames = Frames(*Make(kAruco));
  const auto dictionary = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_6X6_250);
  auto parameters = cv::aruco::DetectorParameters::create();
  parameters->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
  parameters->cornerRefinementWinSize = 5;
  parameters->cornerRefinementMaxIterations = 50;
  parameters->cornerRefinementMinAccuracy = 0.01;
  std::vector<std::vector<cv::Point2f>> corners;
  std::vector<int> ids;
  size_t i = 0, keypoints = 0;
  for (auto _ : state) {
    const GrayImage& frame = frames[i++ % frames.size()];
    const cv::Mat gray(frame.height(), frame.width(), CV_8UC1,
                       const_cast<std::uint8_t*>(frame.data()));
    cv::aruco::detectMarkers(gray, dictionary, corners, ids, parameters);
    keypoints += 4 * ids.size();
    benchmark::DoNotOptimize(corners.data());
  }
  state.counters["keypoints"] =
      benchmark::Counter(static_cast<double>(keypoints) / state.iterations());
}

void BM_AprilTagDirect(benchmark::State& state, float decimate, bool refine_edges,
                       int min_white_black_diff) {
  const std::vector<GrayImage> frames = Frames(*Make(kAprilTag));
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* td = apriltag_detector_create();
  td->quad_decimate = decimate;
  td->quad_sigma = 0.0f;
  td->refine_edges = refine_edges;
  td->qtp.min_white_black_diff = min_white_black_diff;
  td->decode_sharpening = 0.25;
  td->nthreads = 1;
  apriltag_detector_add_family_bits(td, family, 1);
  size_t i = 0, keypoints = 0;
  for (auto _ : state) {
    const GrayImage& frame = frames[i++ % frames.size()];
    image_u8_t image{frame.width(), frame.height(), frame.width(),
                     const_cast<std::uint8_t*>(frame.data())};
    zarray_t* detections = apriltag_detector_detect(td, &image);
    keypoints += 4 * zarray_size(detections);
    apriltag_detections_destroy(detections);
  }
  state.counters["keypoints"] =
      benchmark::Counter(static_cast<double>(keypoints) / state.iterations());
  apriltag_detector_destroy(td);
  tag36h11_destroy(family);
}

BENCHMARK_CAPTURE(BM_Plugin, aruco, kAruco)->Name("BM_aruco/plugin")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Plugin, aruco_library_corners, kArucoLibraryCorners)
    ->Name("BM_aruco/plugin_library_corners")
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ArucoDirect)->Name("BM_aruco/direct")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Plugin, apriltag_board, kAprilTag)
    ->Name("BM_apriltag_board/plugin")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Plugin, apriltag_library_corners, kAprilTagLibraryCorners)
    ->Name("BM_apriltag_board/plugin_library_corners")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_AprilTagDirect, decimate2, 2.0f, true, 20)
    ->Name("BM_apriltag_board/direct")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Plugin, apriltag_full_resolution, kAprilTagFullResolution)
    ->Name("BM_apriltag_board/plugin_full_resolution")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_AprilTagDirect, decimate1, 1.0f, true, 5)
    ->Name("BM_apriltag_board/direct_full_resolution")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Plugin, apriltag_no_refine_edges, kAprilTagNoRefineEdges)
    ->Name("BM_apriltag_board/plugin_no_refine_edges")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_AprilTagDirect, decimate2_no_refine_edges, 2.0f, false, 20)
    ->Name("BM_apriltag_board/direct_no_refine_edges")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Plugin, apriltag_white_black_5, kAprilTagWhiteBlack5)
    ->Name("BM_apriltag_board/plugin_min_white_black_diff_5")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_AprilTagDirect, decimate2_white_black_5, 2.0f, true, 5)
    ->Name("BM_apriltag_board/direct_min_white_black_diff_5")
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cellmetry

BENCHMARK_MAIN();
