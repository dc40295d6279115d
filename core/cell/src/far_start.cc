// Starts far from the closed form's (far_start.h).
#include "far_start.h"

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/workcell_data.h"
#include "cellmetry/cell/workcell_initial.h"

namespace cellmetry {
namespace {

// A held frame's "start" is its value, not a guess to compare.
bool AnyFree(const std::array<bool, 6>& free) {
  for (bool f : free) {
    if (f) return true;
  }
  return false;
}

void AddIfFar(const std::string& frame, const Pose& given, const Pose& closed,
              std::vector<FarStart>* far) {
  const double distance = (given.t - closed.t).norm();
  const double angle = RvecFromRotation(given.R * closed.R.transpose()).norm();
  if (distance > kFarStartMm || angle > kFarStartRad) far->push_back({frame, distance, angle});
}

}  // namespace

std::vector<FarStart> FarStarts(const WorkcellProblem& spec, const Recording& recording,
                                WorkcellProblem* without_starts) {
  bool started = false;
  WorkcellProblem closed = spec;
  for (WorkcellRobot& robot : closed.robots) {
    if (!robot.base_start || !AnyFree(robot.base.free)) continue;
    started = true;
    robot.base_start.reset();
  }
  for (auto& [name, camera] : closed.cameras) {
    if (!camera.start || !AnyFree(camera.free)) continue;
    started = true;
    camera.start.reset();
  }
  if (!started || spec.warm_start) return {};
  WorkcellEstimate start;
  try {
    start = InitialEstimate(closed, recording, PrepareWorkcellData(closed, recording));
  } catch (const InputError&) {
    return {};  // the starts are what places the cell: nothing to compare them with
  }
  std::vector<FarStart> far;
  for (const WorkcellRobot& robot : spec.robots) {
    const auto it = start.T_world_base.find(robot.name);
    if (robot.base_start && AnyFree(robot.base.free) && it != start.T_world_base.end()) {
      AddIfFar(robot.name + ".base", *robot.base_start, it->second, &far);
    }
  }
  for (const auto& [name, camera] : spec.cameras) {
    const auto it = start.T_world_cam.find(name);
    if (camera.start && AnyFree(camera.free) && it != start.T_world_cam.end()) {
      AddIfFar(name, *camera.start, it->second, &far);
    }
  }
  if (!far.empty() && without_starts != nullptr) *without_starts = std::move(closed);
  return far;
}

}  // namespace cellmetry
