// Joint ranges of a calibration and the held-out poses beyond them (joint_ranges.h).
#include "cellmetry/cell/joint_ranges.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

namespace cellmetry {
namespace {

// The RMS of the points' 3D errors; NaN for none.
double RmsOfPoints(const std::vector<const HeldOutPoint*>& points) {
  if (points.empty()) return NAN;
  double sum2 = 0.0;
  for (const HeldOutPoint* p : points) sum2 += p->error_mm.squaredNorm();
  return std::sqrt(sum2 / static_cast<double>(points.size()));
}

std::string Degrees(double rad) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", rad * 180.0 / M_PI);
  return text;
}

std::string Millimetres(double mm) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f mm", mm);
  return text;
}

}  // namespace

std::vector<JointRange> JointRanges(const Recording& recording) {
  std::vector<JointRange> ranges;
  for (const auto& [robot, joints] : recording.robots) {
    for (int j = 0; j < joints; ++j) {
      JointRange range{robot, j + 1, HUGE_VAL, -HUGE_VAL};
      for (const Sample& s : recording.samples) {
        if (s.robot != robot || j >= static_cast<int>(s.q.size())) continue;
        range.min_rad = std::min(range.min_rad, s.q[j]);
        range.max_rad = std::max(range.max_rad, s.q[j]);
      }
      if (range.min_rad <= range.max_rad) ranges.push_back(range);
    }
  }
  return ranges;
}

void RecordJointRanges(const Recording& recording, WorkcellResult* result) {
  const std::vector<JointRange> ranges = JointRanges(recording);
  for (RobotModelRecord& record : result->robot_models) {
    record.joint_ranges_rad.clear();
    for (const JointRange& range : ranges) {
      if (range.robot != record.robot) continue;
      record.joint_ranges_rad.emplace_back(range.min_rad, range.max_rad);
    }
  }
}

void MarkBeyondCalibration(const Recording& calibration, const Recording& held_out,
                           HeldOutSetupScore* score) {
  BeyondCalibration& beyond = score->beyond_calibration;
  beyond = BeyondCalibration{};
  std::set<int> scored_samples;
  for (const HeldOutPoint& p : score->points) scored_samples.insert(p.sample);
  std::set<int> samples_beyond;
  for (const JointRange& range : JointRanges(calibration)) {
    JointBeyondCalibration joint{
        range.robot, range.joint, range.min_rad, range.max_rad, HUGE_VAL, -HUGE_VAL, 0};
    std::set<int> poses;
    for (int id : scored_samples) {
      const int index = held_out.SampleIndex(id);
      if (index < 0) continue;
      const Sample& s = held_out.samples[index];
      if (s.robot != range.robot || range.joint > static_cast<int>(s.q.size())) continue;
      const double q = s.q[range.joint - 1];
      joint.scored_min_rad = std::min(joint.scored_min_rad, q);
      joint.scored_max_rad = std::max(joint.scored_max_rad, q);
      if (q < range.min_rad - kJointRangeToleranceRad ||
          q > range.max_rad + kJointRangeToleranceRad) {
        poses.insert(s.pose);
        samples_beyond.insert(id);
      }
    }
    joint.poses = static_cast<int>(poses.size());
    if (joint.poses > 0) beyond.joints.push_back(joint);
  }
  std::vector<const HeldOutPoint*> within, outside;
  std::set<int> poses_beyond;
  for (HeldOutPoint& p : score->points) {
    p.beyond_calibration = samples_beyond.count(p.sample) > 0;
    (p.beyond_calibration ? outside : within).push_back(&p);
    if (p.beyond_calibration) poses_beyond.insert(p.pose);
  }
  beyond.poses = static_cast<int>(poses_beyond.size());
  beyond.rms_within_mm = RmsOfPoints(within);
  beyond.rms_beyond_mm = RmsOfPoints(outside);
}

std::string BeyondCalibrationText(const HeldOutSetupScore& score) {
  const BeyondCalibration& beyond = score.beyond_calibration;
  if (beyond.poses == 0) return "";
  std::string joints;
  for (const JointBeyondCalibration& j : beyond.joints) {
    joints += (joints.empty() ? "" : "; ") + j.robot + " joint " + std::to_string(j.joint) +
              " reads " + Degrees(j.scored_min_rad) + " to " + Degrees(j.scored_max_rad) +
              " deg against the calibration's " + Degrees(j.calibration_min_rad) + " to " +
              Degrees(j.calibration_max_rad) + " (" + std::to_string(j.poses) + " poses beyond)";
  }
  std::string text = std::to_string(beyond.poses) + " of " + std::to_string(score.scored_poses) +
                     " scored poses go beyond the joint ranges the calibration's poses span (" +
                     joints + "): RMS " + Millimetres(beyond.rms_beyond_mm) + " there";
  text += std::isnan(beyond.rms_within_mm) ? ", no pose within"
                                           : ", " + Millimetres(beyond.rms_within_mm) + " within";
  return text +
         ". There the model is extrapolated, and a point's sigma holds only what the model "
         "contains.";
}

}  // namespace cellmetry
