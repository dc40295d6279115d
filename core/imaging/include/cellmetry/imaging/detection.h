// `cellmetry detect`: run a detector plugin over a recording's images and write its observations.
//
// Job (`job: detect`), one target and one camera:
//   recording: <folder with images.csv>
//   detector: {type: dot, ...}            # any detector plugin and its options
//   target: marker                        # the target name the observations get
//   camera: {name: stereo, stereo: rig.yaml}   or   {name: cam1, mono: calibration.yaml}
//   origin_id: 0                          # stereo: a keypoint at the target's origin (else the
//                                         # layout is fitted to every keypoint both views see)
//   threads: 0                            # 0: every core
// or several (a workcell: a board on the world, a 3D board on the tool, several cameras):
//   targets: {world: {detector: {...}}, tool: {detector: {...}, origin_id: 0}}
//   cameras: {cam1: {mono: cam1.yaml}, cam2: {mono: cam2.yaml}}
// Every image of the job's cameras is read once and every target's detector run on it.
//
// Every (image, target) result (keypoints, or why it failed) is appended to
// <recording>/detections.jsonl as soon as it is known and flushed, one line each. A rerun reads
// that log, drops a torn last line, and only does what is not in it: an interrupted run loses no
// finished image and duplicates none. Then observations.csv is written (atomically) from the
// whole log: stereo views triangulated (position + covariance), mono views by PnP (pose +
// position covariance).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/imaging/imaging.h"
#include "cellmetry/model/detector.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

struct DetectJob {
  std::string file;
  std::string recording;
  std::vector<TargetMarker> targets;
  std::map<std::string, ImagingCamera> cameras;  // images of other cameras are left alone
  int threads = 0;
};

DetectJob LoadDetectJob(const std::string& path, Registry& registry);

struct ImageDetection {
  int sample = 0;
  std::string camera;
  std::string view;
  std::string target;
  std::string path;
  Detection detection;
  double time_ms = 0.0;
};

// Reads a detection log (<recording>/detections.jsonl, the one RunDetection appends to): every
// (image, target) pair finished by earlier runs. A torn last line (a run killed mid-write) is
// dropped and the log rewritten without it, so appending continues on a clean line.
std::vector<ImageDetection> ReadDetectionLog(const std::string& path);

struct DetectSummary {
  int images = 0;                       // of the job's cameras in images.csv
  int already_done = 0;                 // (image, target) pairs in the log from an earlier run
  int processed = 0;                    // (image, target) pairs done by this run
  int found = 0;                        // over the whole log
  int observations = 0;                 // written to observations.csv
  std::map<std::string, int> failures;  // "<target>: <reason>" -> images
};

// `limit` > 0 stops after that many new images (each with all its targets) (an interruption, for
// tests and for splitting work); the next run continues.
DetectSummary RunDetection(const DetectJob& job, Registry& registry, int limit = 0);

}  // namespace cellmetry
