#include "cellmetry/detection.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <tuple>

#include "cellmetry/atomic_file.h"
#include "cellmetry/error.h"
#include "cellmetry/image.h"
#include "cellmetry/job.h"
#include "cellmetry/progress.h"
#include "cellmetry/recording.h"
#include "cellmetry/target_pose.h"

namespace cellmetry {
namespace {

constexpr const char* kLog = "detections.jsonl";
using ImageKey = std::tuple<int, std::string, std::string>;  // sample, camera, view

nlohmann::json ToJson(const ImageDetection& d) {
  nlohmann::json keypoints = nlohmann::json::array();
  for (const auto& k : d.detection.keypoints) {
    keypoints.push_back({k.id, k.pixel.x(), k.pixel.y(), k.covariance_px2(0, 0),
                         k.covariance_px2(0, 1), k.covariance_px2(1, 1)});
  }
  return {{"sample", d.sample}, {"camera", d.camera},   {"view", d.view},
          {"path", d.path},     {"failure", d.detection.failure},
          {"keypoints", keypoints}, {"time_ms", d.time_ms}};
}

ImageDetection FromJson(const nlohmann::json& j) {
  ImageDetection d;
  d.sample = j.at("sample").get<int>();
  d.camera = j.at("camera").get<std::string>();
  d.view = j.at("view").get<std::string>();
  d.path = j.at("path").get<std::string>();
  d.detection.failure = j.at("failure").get<std::string>();
  d.time_ms = j.at("time_ms").get<double>();
  for (const auto& k : j.at("keypoints")) {
    Keypoint kp;
    kp.id = k.at(0).get<int>();
    kp.pixel = Eigen::Vector2d(k.at(1).get<double>(), k.at(2).get<double>());
    kp.covariance_px2 << k.at(3).get<double>(), k.at(4).get<double>(), k.at(4).get<double>(),
        k.at(5).get<double>();
    d.detection.keypoints.push_back(kp);
  }
  return d;
}

// The finished images of earlier runs. A torn last line (a run killed mid-write) is dropped and
// the log rewritten without it, so that appending continues on a clean line.
std::vector<ImageDetection> ReadLog(const std::string& path) {
  std::vector<ImageDetection> done;
  if (!std::filesystem::exists(path)) return done;
  std::ifstream in(path);
  std::string line, clean;
  bool torn = false;
  while (std::getline(in, line)) {
    try {
      done.push_back(FromJson(nlohmann::json::parse(line)));
      clean += line + "\n";
    } catch (const std::exception&) {
      torn = true;
      break;
    }
  }
  if (torn) AtomicWriteFile(path, clean);
  return done;
}

ImageDetection DetectOne(const DetectJob& job, const ImageRef& ref, const std::string& folder,
                         Detector& detector) {
  ImageDetection out;
  out.sample = ref.sample;
  out.camera = ref.camera;
  out.view = ref.view;
  out.path = ref.path;
  const auto start = std::chrono::steady_clock::now();
  try {
    const GrayImage image = ReadGrayImage(folder + "/" + ref.path);
    const PinholeCamera& camera = job.mono ? *job.mono
                                  : ref.view == "right" ? job.rig->right
                                                        : job.rig->left;
    out.detection.failure = camera.SizeMismatch(image.width(), image.height());
    if (out.detection.failure.empty()) {
      out.detection = detector.Detect(image.view());
    }
  } catch (const InputError& e) {
    out.detection.keypoints.clear();
    out.detection.failure = e.what();
  }
  out.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

std::vector<Observation> MakeObservations(const DetectJob& job, const Detector& detector,
                                          const std::vector<ImageDetection>& log,
                                          std::map<std::string, int>* failures) {
  std::map<std::pair<int, std::string>, const ImageDetection*> left, right, mono;
  for (const auto& d : log) {
    if (d.camera != job.camera || !d.detection.found()) continue;
    auto& side = d.view == "right" ? right : d.view == "left" ? left : mono;
    side[{d.sample, d.camera}] = &d;
  }
  std::vector<Observation> out;
  auto add = [&](int sample, const Eigen::Vector3d& p, const Eigen::Matrix3d& cov,
                 std::optional<Eigen::Vector3d> rvec) {
    Observation o;
    o.sample = sample;
    o.camera = job.camera;
    o.target = job.target;
    o.position_mm = p;
    o.covariance_mm2 = cov;
    o.rvec = rvec;
    out.push_back(o);
  };
  if (job.rig) {
    for (const auto& [key, l] : left) {
      const auto r = right.find(key);
      if (r == right.end()) continue;
      const auto point = TargetOriginFromStereo(*job.rig, l->detection.keypoints,
                                                r->second->detection.keypoints,
                                                detector.layout(), job.origin_id);
      if (!point) {
        ++(*failures)["the two views do not share enough keypoints to place the target"];
        continue;
      }
      add(key.first, point->p_left_mm, point->covariance_mm2, std::nullopt);
    }
  } else {
    for (const auto& [key, m] : mono) {
      const auto pose = EstimateTargetPose(*job.mono, m->detection.keypoints, detector.layout());
      if (!pose) {
        ++(*failures)["too few layout keypoints for a pose (need 4)"];
        continue;
      }
      add(key.first, pose->T_cam_target.t, pose->covariance.bottomRightCorner<3, 3>(),
          RvecFromRotation(pose->T_cam_target.R));
    }
  }
  return out;
}

}  // namespace

DetectJob LoadDetectJob(const std::string& path, Registry& registry) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"job", "description", "recording", "detector", "target", "camera",
                   "origin_id", "threads"});
  DetectJob job;
  job.file = path;
  job.recording = root.ResolvePath(root["recording"].AsString());
  if (!std::filesystem::is_regular_file(job.recording + "/images.csv")) {
    throw root["recording"].Error("no images.csv in '" + job.recording + "'",
                                  "Point 'recording:' at a recording of images");
  }
  const ConfigNode detector = root["detector"];
  job.detector_type = detector["type"].AsString();
  job.detector_config = detector;
  registry.CreateDetector(job.detector_type, detector);  // bad options fail before any work
  job.target = root["target"].AsString();
  const ConfigNode camera = root["camera"];
  camera.ExpectKeys({"name", "stereo", "mono"});
  job.camera = camera["name"].AsString();
  if (camera.Has("stereo") == camera.Has("mono")) {
    throw camera.Error("give exactly one of 'stereo:' (a rig) or 'mono:' (a camera)",
                       "e.g. camera: {name: stereo, stereo: ../cameras/oakd.yaml}");
  }
  if (camera.Has("stereo")) {
    job.rig = ReadStereoRig(camera.ResolvePath(camera["stereo"].AsString()));
  } else {
    job.mono = ReadCamera(camera.ResolvePath(camera["mono"].AsString()));
  }
  job.origin_id = root.GetInt("origin_id", 0);
  job.threads = root.GetInt("threads", 0);
  return job;
}

DetectSummary RunDetection(const DetectJob& job, Registry& registry, int limit) {
  const Recording recording = ReadRecording(job.recording);
  const std::string log_path = job.recording + "/" + kLog;
  std::vector<ImageDetection> log = ReadLog(log_path);
  std::set<ImageKey> done;
  for (const auto& d : log) done.insert({d.sample, d.camera, d.view});
  DetectSummary summary;
  summary.images = static_cast<int>(recording.images.size());
  std::vector<const ImageRef*> pending;
  for (const auto& ref : recording.images) {
    if (ref.camera != job.camera) continue;
    if (done.count({ref.sample, ref.camera, ref.view})) {
      ++summary.already_done;
    } else if (limit <= 0 || static_cast<int>(pending.size()) < limit) {
      pending.push_back(&ref);
    }
  }
  std::FILE* out = std::fopen(log_path.c_str(), "a");
  if (!out) throw InputError({log_path, 0, 0}, "cannot append to the detection log", "Check permissions");
  std::mutex mutex;
  Progress progress("detecting images", static_cast<int>(pending.size()));
  tbb::enumerable_thread_specific<std::unique_ptr<Detector>> detectors(
      [&] { return registry.CreateDetector(job.detector_type, *job.detector_config); });
  tbb::task_arena arena(job.threads > 0 ? job.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(size_t(0), pending.size(), [&](size_t i) {
      const ImageDetection d = DetectOne(job, *pending[i], job.recording, *detectors.local());
      const std::string line = ToJson(d).dump() + "\n";
      std::lock_guard<std::mutex> lock(mutex);
      std::fwrite(line.data(), 1, line.size(), out);
      std::fflush(out);  // finished work survives an interruption
      log.push_back(d);
      progress.Advance();
    });
  });
  std::fclose(out);
  summary.processed = static_cast<int>(pending.size());
  for (const auto& d : log) {
    if (d.camera != job.camera) continue;
    if (d.detection.found()) {
      ++summary.found;
    } else {
      ++summary.failures[d.detection.failure];
    }
  }
  const auto detector = registry.CreateDetector(job.detector_type, *job.detector_config);
  const std::vector<Observation> observations =
      MakeObservations(job, *detector, log, &summary.failures);
  summary.observations = static_cast<int>(observations.size());
  AtomicWriteFile(job.recording + "/observations.csv", ObservationsCsv(observations));
  return summary;
}

}  // namespace cellmetry
