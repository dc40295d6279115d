// The noise model (noise_model.h): sigma per camera and target, the job's, else the detections'
// covariance (never below the scatter of repeated captures), else that pooled scatter.
#include "cellmetry/estimation/noise_model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <vector>

#include "cellmetry/basics/transform.h"

namespace cellmetry {
namespace {

struct Accumulator {
  Eigen::Vector3d position_ss = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation_ss = Eigen::Vector3d::Zero();
  int position_dof = 0;
  int rotation_dof = 0;
  int groups = 0;
  int fewest = 0;      // captures in the smallest group
  int most = 0;        // and in the largest
  bool world = false;  // a world-fixed target: every capture is one group
};

// Where the floor came from, in words: "spread of 3 repeated captures at each of 250 poses".
std::string RepeatsLabel(const Accumulator& acc) {
  if (acc.world) {
    return "spread of " + std::to_string(acc.most) + " captures of a world-fixed target";
  }
  const std::string captures = acc.fewest == acc.most
                                   ? std::to_string(acc.most)
                                   : std::to_string(acc.fewest) + " to " + std::to_string(acc.most);
  return "spread of " + captures + " repeated captures at " +
         (acc.groups == 1 ? std::string("one pose")
                          : "each of " + std::to_string(acc.groups) + " poses");
}

// Whether every capture of `target` by `camera` shows the same view: a target fixed in the world
// seen by a camera standing still. A camera riding on a robot (eye in hand) sees it from each
// pose anew, as a static camera sees a carried target.
bool OneView(const Recording& recording, const std::string& camera, const std::string& target) {
  return recording.targets.at(target) == kWorldCarrier && !recording.camera_mounts.count(camera);
}

}  // namespace

const TargetNoise& NoiseModel::at(const std::string& camera, const std::string& target) const {
  static const TargetNoise kUnknown;
  const auto it = entries.find({camera, target});
  return it == entries.end() ? kUnknown : it->second;
}

bool NoiseModel::has_unknown() const {
  return std::any_of(entries.begin(), entries.end(),
                     [](const auto& entry) { return entry.second.source == "unknown"; });
}

namespace {

// The captures that should measure the same thing: one camera's views of one target at one
// pose (a world-fixed target: at every pose), in the order of (camera, target, pose).
struct RepeatGroup {
  const std::string* camera;
  const std::string* target;
  int pose;
  std::vector<const Observation*> members;
};

std::vector<RepeatGroup> RepeatGroups(const Recording& recording) {
  // Names and groups looked up by small integers: a map keyed by two strings per observation
  // was most of this estimate's time (exp_a: 15,000 observations, 750 groups).
  std::vector<const std::string*> names;  // cameras and targets, as first met
  auto name_id = [&names](const std::string& name) {
    for (size_t i = 0; i < names.size(); ++i) {
      if (*names[i] == name) return static_cast<int>(i);
    }
    names.push_back(&name);
    return static_cast<int>(names.size()) - 1;
  };
  std::map<std::tuple<int, int, int>, size_t> index;
  std::vector<RepeatGroup> groups;
  std::vector<int> on_world;  // per name id: -1 unknown, else whether a world-fixed target
  for (const auto& obs : recording.observations) {
    const int camera = name_id(obs.camera);
    const int target = name_id(obs.target);
    if (on_world.size() < names.size()) on_world.resize(names.size(), -1);
    if (on_world[target] < 0) on_world[target] = recording.targets.at(obs.target) == kWorldCarrier;
    const bool one_view = on_world[target] && !recording.camera_mounts.count(obs.camera);
    const int pose = one_view ? -1 : recording.samples[recording.SampleIndex(obs.sample)].pose;
    const auto [it, added] = index.emplace(std::make_tuple(camera, target, pose), groups.size());
    if (added) groups.push_back({names[camera], names[target], pose, {}});
    groups[it->second].members.push_back(&obs);
  }
  std::sort(groups.begin(), groups.end(), [](const RepeatGroup& a, const RepeatGroup& b) {
    return std::tie(*a.camera, *a.target, a.pose) < std::tie(*b.camera, *b.target, b.pose);
  });
  return groups;
}

}  // namespace

NoiseModel EstimateRepeatability(const Recording& recording) {
  const std::vector<RepeatGroup> groups = RepeatGroups(recording);
  std::map<NoiseKey, Accumulator> sums;
  for (const RepeatGroup& group : groups) {
    const std::vector<const Observation*>& members = group.members;
    if (members.size() < 2) continue;
    Accumulator& acc = sums[{*group.camera, *group.target}];
    ++acc.groups;
    const int size = static_cast<int>(members.size());
    acc.fewest = acc.groups == 1 ? size : std::min(acc.fewest, size);
    acc.most = std::max(acc.most, size);
    acc.world = OneView(recording, *group.camera, *group.target);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto* o : members) mean += o->position_mm;
    mean /= static_cast<double>(members.size());
    for (const auto* o : members) acc.position_ss += (o->position_mm - mean).cwiseAbs2();
    acc.position_dof += static_cast<int>(members.size()) - 1;

    std::vector<Eigen::Matrix3d> rotations;
    for (const auto* o : members) {
      if (o->rvec) rotations.push_back(RotationFromRvec(o->rvec->data()));
    }
    if (rotations.size() >= 2) {
      const Eigen::Matrix3d R_mean = MeanRotation(rotations);
      for (const auto& R : rotations) acc.rotation_ss += RotationError(R, R_mean).cwiseAbs2();
      acc.rotation_dof += static_cast<int>(rotations.size()) - 1;
    }
  }
  NoiseModel model;
  for (const auto& [key, acc] : sums) {
    TargetNoise noise;
    noise.position_mm = (acc.position_ss / acc.position_dof).cwiseSqrt();
    if (acc.rotation_dof > 0) noise.rotation_rad = (acc.rotation_ss / acc.rotation_dof).cwiseSqrt();
    noise.repeat_groups = acc.groups;
    noise.source = RepeatsLabel(acc);
    model.entries[key] = noise;
  }
  return model;
}

NoiseModel DetectionAccuracy(const Recording& recording) {
  struct Sums {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    Eigen::Vector3d rotation = Eigen::Vector3d::Zero();
    int count = 0;
    bool complete = true;  // every observation carries both covariances
  };
  std::map<NoiseKey, Sums> sums;
  for (const auto& obs : recording.observations) {
    Sums& s = sums[{obs.camera, obs.target}];
    if (!obs.covariance_mm2 || !obs.rotation_covariance_rad2) {
      s.complete = false;
      continue;
    }
    s.position += obs.covariance_mm2->diagonal();
    s.rotation += obs.rotation_covariance_rad2->diagonal();
    ++s.count;
  }
  NoiseModel model;
  for (const auto& [key, s] : sums) {
    if (!s.complete || s.count == 0) continue;
    TargetNoise noise;
    noise.position_mm = (s.position / s.count).cwiseSqrt();
    noise.rotation_rad = (s.rotation / s.count).cwiseSqrt();
    noise.source = "detections (" + std::to_string(s.count) + ")";
    if (OneView(recording, key.first, key.second)) {
      // Every capture of a world-fixed target shows the camera the same view: the detector's
      // systematic error repeats, and only its noise averages out. Together they weigh as one.
      noise.position_mm *= std::sqrt(double(s.count));
      noise.rotation_rad *= std::sqrt(double(s.count));
      noise.source += ", one view repeated";
    }
    model.entries[key] = noise;
  }
  return model;
}

NoiseModel BuildNoiseModel(const Recording& recording, const NoiseSpec& spec) {
  return BuildNoiseModel(recording, spec, EstimateRepeatability(recording));
}

Eigen::Vector3d RowPositionSigma(const TargetNoise& noise, const Observation& observation) {
  if (!noise.per_row || !observation.covariance_mm2) return noise.position_mm;
  return (noise.position_mm.cwiseAbs2() + observation.covariance_mm2->diagonal().cwiseMax(0.0))
      .cwiseSqrt();
}

namespace {

// `noise` for a camera whose rows carry their own covariance: sigma is what the model leaves
// out of every row alike, the job's where it gives one, else unknown (from the residuals, less
// the rows' mean variance); a spread of repeats or detections already holds the rows' own part.
void MakePerRow(const Recording& recording, const std::string& camera, const std::string& target,
                TargetNoise* noise) {
  noise->per_row = true;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (const Observation& o : recording.observations) {
    if (o.camera != camera || o.target != target || !o.covariance_mm2) continue;
    sum += o.covariance_mm2->diagonal().cwiseMax(0.0);
    ++count;
  }
  if (count > 0) noise->mean_row_variance_mm2 = sum / count;
  if (noise->source != "job") {
    *noise = TargetNoise{Eigen::Vector3d::Ones(),     noise->rotation_rad, "unknown", 0, true,
                         noise->mean_row_variance_mm2};
  }
}

}  // namespace

NoiseModel BuildNoiseModel(const Recording& recording, const NoiseSpec& spec,
                           const NoiseModel& repeats) {
  const NoiseModel detections = DetectionAccuracy(recording);
  NoiseModel model;
  for (const auto& camera : recording.cameras) {
    for (const auto& [target, carrier] : recording.targets) {
      TargetNoise noise;
      const auto repeat = repeats.entries.find({camera, target});
      if (repeat != repeats.entries.end()) noise = repeat->second;
      const auto detected = detections.entries.find({camera, target});
      if (detected != detections.entries.end()) {
        const bool has_repeats = repeat != repeats.entries.end();
        noise.position_mm = has_repeats ? detected->second.position_mm.cwiseMax(noise.position_mm)
                                        : detected->second.position_mm;
        noise.rotation_rad = has_repeats
                                 ? detected->second.rotation_rad.cwiseMax(noise.rotation_rad)
                                 : detected->second.rotation_rad;
        noise.source = detected->second.source;
      }
      const auto job_position = spec.position_sigma_mm.find(camera);
      if (job_position != spec.position_sigma_mm.end()) {
        noise.position_mm = job_position->second;
        noise.source = "job";
      }
      const auto job_rotation = spec.rotation_sigma_rad.find(camera);
      if (job_rotation != spec.rotation_sigma_rad.end()) noise.rotation_rad = job_rotation->second;
      if (spec.per_row_cameras.count(camera)) MakePerRow(recording, camera, target, &noise);
      noise.position_mm = noise.position_mm.cwiseMax(spec.floor_mm);
      noise.rotation_rad = noise.rotation_rad.cwiseMax(spec.floor_rad);
      model.entries[{camera, target}] = noise;
    }
  }
  return model;
}

}  // namespace cellmetry
