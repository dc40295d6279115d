// Joint ranges of a calibration and the held-out poses beyond them (joint_ranges.h).
#include "cellmetry/cell/joint_ranges.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "cellmetry/basics/text.h"

namespace cellmetry {
namespace {

// The RMS of the points' 3D errors; NaN for none.
double RmsOfPoints(const std::vector<const HeldOutPoint*>& points) {
  if (points.empty()) return NAN;
  double sum2 = 0.0;
  for (const HeldOutPoint* p : points) sum2 += p->error_mm.squaredNorm();
  return std::sqrt(sum2 / static_cast<double>(points.size()));
}

std::string Millimetres(double mm) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4f mm", mm);
  return text;
}

// Per calibrated joint (as `ranges` lists them): the scored samples' range and the poses beyond
// the calibration's; `samples_beyond` gets each scored sample with any joint beyond.
std::vector<JointBeyondCalibration> JudgeScoredSamples(const std::vector<JointRange>& ranges,
                                                       const Recording& held_out,
                                                       const std::set<int>& scored_samples,
                                                       std::set<int>* samples_beyond) {
  std::map<std::string, JointRangesRad> robot_ranges;  // joint j at j - 1; unrecorded: no limit
  std::vector<JointBeyondCalibration> joints;
  for (const JointRange& r : ranges) {
    JointRangesRad& robot = robot_ranges[r.robot];
    if (static_cast<int>(robot.size()) < r.joint) robot.resize(r.joint, {-HUGE_VAL, HUGE_VAL});
    robot[r.joint - 1] = {r.min_rad, r.max_rad};
    joints.push_back({r.robot, r.joint, r.min_rad, r.max_rad, HUGE_VAL, -HUGE_VAL, 0});
  }
  std::vector<std::set<int>> poses_beyond(joints.size());
  for (int id : scored_samples) {
    const int index = held_out.SampleIndex(id);
    if (index < 0) continue;
    const Sample& s = held_out.samples[index];
    const std::vector<int> outside = JointsOutsideRanges(robot_ranges[s.robot], s.q);
    if (!outside.empty()) samples_beyond->insert(id);
    for (size_t k = 0; k < joints.size(); ++k) {
      JointBeyondCalibration& joint = joints[k];
      if (joint.robot != s.robot || joint.joint > static_cast<int>(s.q.size())) continue;
      const double q = s.q[joint.joint - 1];
      joint.scored_min_rad = std::min(joint.scored_min_rad, q);
      joint.scored_max_rad = std::max(joint.scored_max_rad, q);
      if (std::count(outside.begin(), outside.end(), joint.joint)) poses_beyond[k].insert(s.pose);
    }
  }
  for (size_t k = 0; k < joints.size(); ++k) {
    joints[k].poses = static_cast<int>(poses_beyond[k].size());
  }
  return joints;
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
  std::set<int> scored_samples, samples_beyond;
  for (const HeldOutPoint& p : score->points) scored_samples.insert(p.sample);
  for (const JointBeyondCalibration& joint :
       JudgeScoredSamples(JointRanges(calibration), held_out, scored_samples, &samples_beyond)) {
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

void MarkBeyondCalibration(const WorkcellResult& result, const Recording& fresh,
                           const std::vector<ResidualRow>& rows, RecordingScore* score) {
  std::map<std::string, JointRangesRad> ranges;
  for (const RobotModelRecord& record : result.robot_models) {
    ranges[record.robot] = record.joint_ranges_rad;
  }
  std::set<int> poses, poses_beyond;
  ResidualRms within, outside;
  for (const ResidualRow& row : rows) {
    const int index = fresh.SampleIndex(row.sample);
    if (index < 0) continue;
    const Sample& s = fresh.samples[index];
    const bool beyond = !JointsOutsideRanges(ranges[s.robot], s.q).empty();
    poses.insert(row.pose);
    if (beyond) poses_beyond.insert(row.pose);
    (beyond ? outside : within).Add(row.error);
  }
  within.Finish();
  outside.Finish();
  score->poses = static_cast<int>(poses.size());
  score->poses_beyond_calibration = static_cast<int>(poses_beyond.size());
  score->rms_beyond_calibration_mm = outside.count > 0 ? outside.norm : NAN;
  score->rms_within_calibration_mm = within.count > 0 ? within.norm : NAN;
}

std::string BeyondCalibrationText(const RecordingScore& score) {
  if (score.poses_beyond_calibration == 0) return "";
  std::string text = std::to_string(score.poses_beyond_calibration) + " of " +
                     std::to_string(score.poses) +
                     " poses go beyond the joint ranges the result was fitted on: RMS " +
                     Millimetres(score.rms_beyond_calibration_mm) + " there";
  text += std::isnan(score.rms_within_calibration_mm)
              ? ", no pose within"
              : ", " + Millimetres(score.rms_within_calibration_mm) + " within";
  return text + ". There the model is extrapolated.";
}

}  // namespace cellmetry
