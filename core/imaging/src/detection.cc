// `cellmetry detect` (detection.h): the pending (image, target) pairs detected in parallel and
// appended to a resumable log, then the whole log turned into observations (stereo or PnP).
#include "cellmetry/imaging/detection.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/basics/so3_jacobians.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/config_fields.h"
#include "cellmetry/formats/image.h"
#include "cellmetry/formats/input_file.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/formats/strict_json.h"
#include "cellmetry/imaging/target_pose.h"

namespace cellmetry {
namespace {

constexpr const char* kLog = "detections.jsonl";
using DoneKey =
    std::tuple<int, std::string, std::string, std::string>;          // sample, camera, view, target
using Detectors = std::map<std::string, std::unique_ptr<Detector>>;  // by target

nlohmann::json ToJson(const ImageDetection& d) {
  nlohmann::json keypoints = nlohmann::json::array();
  for (const auto& k : d.detection.keypoints) {
    keypoints.push_back({k.id, k.pixel.x(), k.pixel.y(), k.covariance_px2(0, 0),
                         k.covariance_px2(0, 1), k.covariance_px2(1, 1)});
  }
  return {{"sample", d.sample},     {"camera", d.camera},  {"view", d.view},
          {"target", d.target},     {"path", d.path},      {"failure", d.detection.failure},
          {"keypoints", keypoints}, {"time_ms", d.time_ms}};
}

// A line of the log that is not a detection `detect` could have written: what is wrong with it.
struct NotADetection {
  std::string what;
};

const nlohmann::json& Field(const nlohmann::json& j, const char* key) {
  if (!j.is_object()) throw NotADetection{"not a JSON object"};
  const auto it = j.find(key);
  if (it == j.end()) throw NotADetection{std::string("no '") + key + "'"};
  return *it;
}

// A whole number in [0, 2^31): sample and keypoint ids. Read as JSON integers only, so that a
// float such as 1e30 never reaches a cast to int.
int Id(const nlohmann::json& j, const std::string& what) {
  if (!j.is_number_integer()) throw NotADetection{what + " is not a whole number"};
  if (j.is_number_unsigned() ? j.get<std::uint64_t>() > 0x7fffffffu
                             : (j.get<std::int64_t>() < 0 || j.get<std::int64_t>() > 0x7fffffff)) {
    throw NotADetection{what + " is out of range (0 to 2147483647)"};
  }
  return static_cast<int>(j.get<std::int64_t>());
}

double Finite(const nlohmann::json& j, const std::string& what) {
  if (!j.is_number()) throw NotADetection{what + " is not a number"};
  const double value = j.get<double>();
  if (!std::isfinite(value)) throw NotADetection{what + " is not finite"};
  return value;
}

std::string Text(const nlohmann::json& j, const char* key) {
  const nlohmann::json& v = Field(j, key);
  if (!v.is_string()) throw NotADetection{std::string("'") + key + "' is not a string"};
  return v.get<std::string>();
}

ImageDetection FromJson(const nlohmann::json& j) {
  ImageDetection d;
  d.sample = Id(Field(j, "sample"), "'sample'");
  d.camera = Text(j, "camera");
  d.view = Text(j, "view");
  d.target = Text(j, "target");
  d.path = Text(j, "path");
  d.detection.failure = Text(j, "failure");
  d.time_ms = Finite(Field(j, "time_ms"), "'time_ms'");
  const nlohmann::json& keypoints = Field(j, "keypoints");
  if (!keypoints.is_array()) throw NotADetection{"'keypoints' is not a list"};
  for (const auto& k : keypoints) {
    if (!k.is_array() || k.size() != 6) {
      throw NotADetection{"a keypoint is not [id, x, y, cov_xx, cov_xy, cov_yy]"};
    }
    Keypoint kp;
    kp.id = Id(k[0], "a keypoint id");
    kp.pixel = Eigen::Vector2d(Finite(k[1], "a keypoint's x"), Finite(k[2], "a keypoint's y"));
    const double xx = Finite(k[3], "a keypoint's cov_xx"), xy = Finite(k[4], "a keypoint's cov_xy"),
                 yy = Finite(k[5], "a keypoint's cov_yy");
    // A covariance: symmetric by construction, and positive semi-definite.
    if (xx < 0 || yy < 0 || xx * yy < xy * xy) {
      throw NotADetection{"a keypoint's covariance is not positive semi-definite"};
    }
    kp.covariance_px2 << xx, xy, xy, yy;
    d.detection.keypoints.push_back(kp);
  }
  return d;
}

}  // namespace

// The finished images of earlier runs (detection.h). Only the last line can be torn (a run
// killed mid-write): it is dropped and the log rewritten without it. A bad line before it is
// not a torn write but a damaged log, refused at its line: dropping it and everything after it
// would silently lose finished work.
std::vector<ImageDetection> ReadDetectionLog(const std::string& path) {
  std::vector<ImageDetection> done;
  std::error_code ec;
  const auto status = std::filesystem::symlink_status(path, ec);
  if (!std::filesystem::exists(status)) return done;
  // The log is appended to in place: through a link, detect would write to a file outside the
  // recording that something else may own.
  if (std::filesystem::is_symlink(status)) {
    throw InputError({path, 0, 0},
                     "the detection log is a link; detect appends to it in place and would write "
                     "through the link to a file that may lie outside the recording",
                     "Replace the link by a copy of the file it names (cp --remove-destination "
                     "TARGET " +
                         path + "), or delete it to detect everything again");
  }
  const std::string text = ReadRegularFile(path, kMaxTableBytes, "Check permissions");
  std::vector<std::string> lines;
  for (size_t begin = 0; begin < text.size();) {
    const size_t end = std::min(text.find('\n', begin), text.size());
    lines.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  const char* const hint =
      "Delete the line (its image is detected again on the next run), or the whole log to "
      "detect everything again";
  std::string clean;
  bool rewrite = !text.empty() && text.back() != '\n';  // appending must start on a new line
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const bool last = i + 1 == lines.size();
    try {
      done.push_back(FromJson(ParseStrictJson<nlohmann::json>(line)));
      clean += line + "\n";
    } catch (const nlohmann::json::exception& e) {
      if (last) {  // torn last line
        rewrite = true;
        break;
      }
      const auto* parse = dynamic_cast<const nlohmann::json::parse_error*>(&e);
      const int column = parse && parse->byte <= line.size() ? static_cast<int>(parse->byte) : 0;
      throw InputError({path, static_cast<int>(i + 1), column},
                       "a line of the detection log is not JSON", hint);
    } catch (const StrictJsonError& bad) {  // a hand edit, never a torn write
      throw InputError({path, static_cast<int>(i + 1), 0},
                       "a line of the detection log is not a detection: " + bad.what, hint);
    } catch (const NotADetection& bad) {
      if (last) {
        rewrite = true;
        break;
      }
      throw InputError({path, static_cast<int>(i + 1), 0},
                       "a line of the detection log is not a detection: " + bad.what, hint);
    }
  }
  if (rewrite) AtomicWriteFile(path, clean);
  return done;
}

namespace {

Detectors MakeDetectors(const DetectJob& job, Registry& registry) {
  Detectors detectors;
  for (const auto& marker : job.targets) {
    detectors[marker.target] =
        registry.CreateDetector(marker.detector_type, *marker.detector_config);
  }
  return detectors;
}

// Reads the image once and runs the detector of every target in `targets` on it. An unreadable
// image or one of the wrong size is a failure of each of them.
std::vector<ImageDetection> DetectOne(const DetectJob& job, const ImageRef& ref,
                                      const std::vector<std::string>& targets,
                                      Detectors& detectors) {
  std::vector<ImageDetection> out;
  const auto start = std::chrono::steady_clock::now();
  std::string failure;
  GrayImage image;
  try {
    image = ReadGrayImage(job.recording + "/" + ref.path);
    failure = job.cameras.at(ref.camera).View(ref.view).SizeMismatch(image.width(), image.height());
  } catch (const InputError& e) {
    failure = e.what();
  }
  const double read_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  for (const auto& target : targets) {
    ImageDetection d;
    d.sample = ref.sample;
    d.camera = ref.camera;
    d.view = ref.view;
    d.target = target;
    d.path = ref.path;
    const auto begin = std::chrono::steady_clock::now();
    d.detection.failure = failure;
    if (failure.empty()) d.detection = detectors.at(target)->Detect(image.view());
    d.time_ms =
        read_ms / targets.size() +
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
    out.push_back(std::move(d));
  }
  return out;
}

std::vector<Observation> MakeObservations(const DetectJob& job, const Detectors& detectors,
                                          const std::vector<ImageDetection>& log,
                                          std::map<std::string, int>* failures) {
  using ViewKey = std::tuple<std::string, std::string, int>;  // camera, target, sample
  std::map<ViewKey, const ImageDetection*> left, right, mono;
  for (const auto& d : log) {
    if (!job.cameras.count(d.camera) || !detectors.count(d.target) || !d.detection.found())
      continue;
    auto& side = d.view == "right" ? right : d.view == "left" ? left : mono;
    side[{d.camera, d.target, d.sample}] = &d;
  }
  std::vector<Observation> out;
  auto add = [&](const ViewKey& key, const Eigen::Vector3d& p, const Eigen::Matrix3d& cov) {
    Observation o;
    std::tie(o.camera, o.target, o.sample) = key;
    o.position_mm = p;
    o.covariance_mm2 = cov;
    out.push_back(o);
  };
  std::map<std::string, int> origin_id;
  for (const auto& marker : job.targets) origin_id[marker.target] = marker.origin_id;
  for (const auto& [key, l] : left) {
    const auto r = right.find(key);
    if (r == right.end()) continue;
    const auto& [camera, target, sample] = key;
    const auto point = TargetOriginFromStereo(*job.cameras.at(camera).rig, l->detection.keypoints,
                                              r->second->detection.keypoints,
                                              detectors.at(target)->layout(), origin_id.at(target));
    if (!point) {
      ++(*failures)[target + ": the two views do not share enough keypoints to place the target"];
      continue;
    }
    add(key, point->p_left_mm, point->covariance_mm2);
  }
  for (const auto& [key, m] : mono) {
    const auto& [camera, target, sample] = key;
    const auto pose = EstimateTargetPose(*job.cameras.at(camera).mono, m->detection.keypoints,
                                         detectors.at(target)->layout());
    if (!pose) {
      ++(*failures)[target + ": too few layout keypoints for a pose (need 4)"];
      continue;
    }
    add(key, pose->T_cam_target.t, pose->covariance.bottomRightCorner<3, 3>());
    // The rotation vector's covariance, as small rotations about the camera axes (the
    // calibrations' rotation error): R(rvec + d) = Exp(J_l(rvec) d) R(rvec).
    const Eigen::Vector3d rvec = RvecFromRotation(pose->T_cam_target.R);
    const Eigen::Matrix3d J_l = LeftJacobian(rvec);
    out.back().rvec = rvec;
    out.back().rotation_covariance_rad2 =
        J_l * pose->covariance.topLeftCorner<3, 3>() * J_l.transpose();
  }
  std::sort(out.begin(), out.end(), [](const Observation& a, const Observation& b) {
    return std::tie(a.sample, a.camera, a.target) < std::tie(b.sample, b.camera, b.target);
  });
  return out;
}

// The one-target, one-camera form of the job (detection.h).
void ReadSingleForm(const ConfigNode& root, Registry& registry, DetectJob* job) {
  TargetMarker marker = ReadTargetMarker(root["target"].AsString(), root["detector"], registry);
  marker.origin_id = root.GetInt("origin_id", 0);
  job->targets.push_back(marker);
  const ConfigNode camera = root["camera"];
  camera.ExpectKeys({"name", "stereo", "mono"});
  job->cameras[camera["name"].AsString()] = ReadImagingCamera(camera);
}

void ReadMultipleForm(const ConfigNode& root, Registry& registry, DetectJob* job) {
  const ConfigNode targets = root["targets"];
  for (const auto& name : targets.Keys()) {
    const ConfigNode node = targets[name];
    node.ExpectKeys({"detector", "origin_id"});
    TargetMarker marker = ReadTargetMarker(name, node["detector"], registry);
    marker.origin_id = node.GetInt("origin_id", 0);
    job->targets.push_back(marker);
  }
  const ConfigNode cameras = root["cameras"];
  for (const auto& name : cameras.Keys()) {
    cameras[name].ExpectKeys({"stereo", "mono"});
    job->cameras[name] = ReadImagingCamera(cameras[name]);
  }
}

// An image of the job's cameras with the targets the log has no entry for yet.
struct PendingImage {
  const ImageRef* image;
  std::vector<std::string> targets;
};

// The images still to detect (`limit` > 0: at most that many), counting every image of the
// job's cameras and each image-target pair the log already has.
std::vector<PendingImage> Pending(const DetectJob& job, const Recording& recording,
                                  const std::vector<ImageDetection>& log, int limit,
                                  DetectSummary* summary) {
  std::set<DoneKey> done;
  for (const auto& d : log) done.insert({d.sample, d.camera, d.view, d.target});
  std::vector<PendingImage> pending;
  for (const auto& ref : recording.images) {
    const auto camera = job.cameras.find(ref.camera);
    if (camera == job.cameras.end() || !camera->second.HasView(ref.view)) continue;
    ++summary->images;
    PendingImage work{&ref, {}};
    for (const auto& marker : job.targets) {
      if (done.count({ref.sample, ref.camera, ref.view, marker.target})) {
        ++summary->already_done;
      } else {
        work.targets.push_back(marker.target);
      }
    }
    if (!work.targets.empty() && (limit <= 0 || static_cast<int>(pending.size()) < limit)) {
      pending.push_back(work);
    }
  }
  return pending;
}

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

// Detects the pending images on every core (or job.threads), each image's lines appended to the
// log file as soon as they are found, so that finished work survives an interruption.
void DetectAndLog(const DetectJob& job, Registry& registry,
                  const std::vector<PendingImage>& pending, const std::string& log_path,
                  std::vector<ImageDetection>* log, DetectSummary* summary) {
  const std::unique_ptr<std::FILE, FileCloser> out(std::fopen(log_path.c_str(), "a"));
  if (!out) {
    throw InputError({log_path, 0, 0}, "cannot append to the detection log", "Check permissions");
  }
  std::mutex mutex;
  Progress progress("detecting images", static_cast<int>(pending.size()));
  tbb::enumerable_thread_specific<Detectors> detectors(
      [&] { return MakeDetectors(job, registry); });
  tbb::task_arena arena(job.threads > 0 ? job.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(size_t(0), pending.size(), [&](size_t i) {
      const std::vector<ImageDetection> found =
          DetectOne(job, *pending[i].image, pending[i].targets, detectors.local());
      std::string lines;
      for (const auto& d : found) lines += ToJson(d).dump() + "\n";
      std::lock_guard<std::mutex> lock(mutex);
      std::fwrite(lines.data(), 1, lines.size(), out.get());
      std::fflush(out.get());
      log->insert(log->end(), found.begin(), found.end());
      summary->processed += static_cast<int>(found.size());
      progress.Advance();
    });
  });
}

}  // namespace

DetectJob LoadDetectJob(const std::string& path, Registry& registry) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  // A workcell job given to `detect` was refused on its first key the detect job lacks.
  if (root.Has("job") && root["job"].AsString() != "detect") {
    throw root["job"].Error("not a detect job (job: " + root["job"].AsString() + ")",
                            "Run it with the command its kind names; a detect job says "
                            "job: detect");
  }
  root.ExpectKeys({"job", "description", "recording", "detector", "target", "camera", "origin_id",
                   "targets", "cameras", "threads"});
  DetectJob job;
  job.file = path;
  job.recording = root.ResolvePath(root["recording"].AsString());
  if (!std::filesystem::is_regular_file(job.recording + "/images.csv")) {
    throw root["recording"].Error("no images.csv in '" + job.recording + "'",
                                  "Point 'recording:' at a recording of images");
  }
  const bool single = root.Has("detector") || root.Has("target") || root.Has("camera");
  if (single == (root.Has("targets") || root.Has("cameras"))) {
    throw root.Error(
        "give either detector:, target: and camera: (one of each) or targets: and "
        "cameras: (several)",
        "See docs/formats.md, `job: detect`");
  }
  if (single) {
    ReadSingleForm(root, registry, &job);
  } else {
    ReadMultipleForm(root, registry, &job);
  }
  job.threads = root.GetIntIn("threads", 0, 0, 1024, "0 uses every core; or give a count");
  return job;
}

namespace {

// The first line of every observations.csv `detect` writes: how a rerun knows the file is its
// own to replace (CSV readers skip a line that starts with '#').
constexpr const char* kDetectedMark =
    "# written by cellmetry detect from detections.jsonl; the next detect replaces this file\n";

// `detect` replaces observations.csv whole; one it did not write (a user's own measurements, an
// imported table) is refused before any work, never overwritten.
void RequireOwnObservations(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::symlink_status(path, ec);
  if (!std::filesystem::exists(status)) return;
  std::string first;
  if (std::filesystem::is_regular_file(status)) {
    std::ifstream in(path, std::ios::binary);
    std::getline(in, first);
  }
  if (first + "\n" == kDetectedMark) return;
  throw InputError({path, 0, 0},
                   "observations.csv was not written by cellmetry detect, which would replace it "
                   "with what it detects",
                   "Move the file out of the recording (or rename it) to keep it; delete it if "
                   "an older cellmetry detect wrote it");
}

}  // namespace

DetectSummary RunDetection(const DetectJob& job, Registry& registry, int limit) {
  RequireOwnObservations(job.recording + "/observations.csv");
  const Recording recording = ReadRecording(job.recording);
  for (const auto& [camera, imaging] : job.cameras) {
    if (!recording.HasCamera(camera)) {
      throw InputError({job.file, 0, 0}, "the recording has no camera '" + camera + "'",
                       "Name the cameras of " + job.recording + "/recording.yaml");
    }
  }
  const std::string log_path = job.recording + "/" + kLog;
  std::vector<ImageDetection> log = ReadDetectionLog(log_path);
  DetectSummary summary;
  const std::vector<PendingImage> pending = Pending(job, recording, log, limit, &summary);
  // detect's own files in a recording cellmetry made: a later `simulate` to the same folder
  // replaces them with the rest instead of refusing them as a user's.
  NoteOutputFile(job.recording, kLog);
  NoteOutputFile(job.recording, "observations.csv");
  DetectAndLog(job, registry, pending, log_path, &log, &summary);
  const Detectors layouts = MakeDetectors(job, registry);
  for (const auto& d : log) {
    if (!job.cameras.count(d.camera) || !layouts.count(d.target)) continue;
    if (d.detection.found()) {
      ++summary.found;
    } else {
      ++summary.failures[d.target + ": " + d.detection.failure];
    }
  }
  const std::vector<Observation> observations =
      MakeObservations(job, layouts, log, &summary.failures);
  summary.observations = static_cast<int>(observations.size());
  AtomicWriteFile(job.recording + "/observations.csv",
                  kDetectedMark + ObservationsCsv(observations));
  return summary;
}

}  // namespace cellmetry
