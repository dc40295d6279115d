// CheckRobotsMove and StillJoints (motion_check.h).
#include "cellmetry/cell/motion_check.h"

#include <algorithm>
#include <cstdio>
#include <limits>

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

// Per joint of one robot, the smallest and largest reading over the samples the fit uses.
struct JointSpan {
  std::vector<double> low, high;
  int samples = 0;
  const Sample* first = nullptr;
  bool moves(size_t j) const { return high[j] - low[j] > kStillJointRad; }
};

std::vector<JointSpan> Spans(const WorkcellProblem& spec, const Recording& recording,
                             const WorkcellData& data) {
  std::vector<JointSpan> spans(spec.robots.size());
  std::vector<int> last_sample(spec.robots.size(), -1);
  for (const ToolMeasurement& m : data.tools) {
    if (last_sample[m.robot] == m.sample_index) continue;
    last_sample[m.robot] = m.sample_index;
    const Sample& sample = recording.samples[m.sample_index];
    JointSpan& span = spans[m.robot];
    if (!span.first) {
      span.first = &sample;
      span.low.assign(sample.q.size(), std::numeric_limits<double>::infinity());
      span.high.assign(sample.q.size(), -std::numeric_limits<double>::infinity());
    }
    ++span.samples;
    for (size_t j = 0; j < sample.q.size() && j < span.low.size(); ++j) {
      span.low[j] = std::min(span.low[j], sample.q[j]);
      span.high[j] = std::max(span.high[j], sample.q[j]);
    }
  }
  return spans;
}

bool AnythingFree(const WorkcellRobot& robot) {
  auto any = [](const std::array<bool, 6>& free) {
    return std::any_of(free.begin(), free.end(), [](bool f) { return f; });
  };
  if (any(robot.base.free)) return true;
  for (const WorkcellTool& tool : robot.tools) {
    if (any(tool.flange_tool.free)) return true;
  }
  return std::any_of(robot.model_parameters.begin(), robot.model_parameters.end(),
                     [](const Parameter& p) { return !p.fixed; });
}

}  // namespace

void CheckRobotsMove(const WorkcellProblem& spec, const Recording& recording,
                     const WorkcellData& data) {
  const std::vector<JointSpan> spans = Spans(spec, recording, data);
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    const JointSpan& span = spans[r];
    if (span.samples < 2 || !AnythingFree(spec.robots[r])) continue;
    bool moves = false;
    for (size_t j = 0; j < span.low.size(); ++j) moves |= span.moves(j);
    if (moves) continue;
    throw InputError({recording.folder + "/samples.csv", span.first->line, 0},
                     "every one of the " + std::to_string(span.samples) + " samples of robot '" +
                         spec.robots[r].name +
                         "' that the fit uses has the same joint "
                         "readings: its base, tools and model cannot be told apart",
                     "Record poses that move the robot, or hold its base, tools and model "
                     "(free: none)");
  }
}

std::vector<std::string> StillJoints(const WorkcellProblem& spec, const Recording& recording,
                                     const WorkcellData& data) {
  const std::vector<JointSpan> spans = Spans(spec, recording, data);
  std::vector<std::string> warnings;
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    const JointSpan& span = spans[r];
    if (span.samples < 2) continue;
    size_t moving = 0;
    for (size_t j = 0; j < span.low.size(); ++j) moving += span.moves(j);
    if (moving == 0) continue;  // CheckRobotsMove's case
    for (size_t j = 0; j < span.low.size(); ++j) {
      if (span.moves(j)) continue;
      char reading[64];
      std::snprintf(reading, sizeof reading, "%.4f rad", span.low[j]);
      warnings.push_back("joint " + std::to_string(j + 1) + " of " + spec.robots[r].name +
                         " reads " + reading + " in every one of its " +
                         std::to_string(span.samples) +
                         " samples while other joints move: "
                         "its geometry cannot be told from its neighbours'; check its encoder "
                         "(samples.csv q" +
                         std::to_string(j + 1) +
                         "), or record poses that "
                         "move it");
    }
  }
  return warnings;
}

}  // namespace cellmetry
