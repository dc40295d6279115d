// CheckLengthScale (length_scale_check.h): the observed motion of each carried target against
// the robot config's motion of the flange, at the same joint readings.
#include "length_scale_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <vector>

#include "cellmetry/basics/statistics.h"
#include "cellmetry/basics/text.h"
#include "cellmetry/formats/config_node.h"

namespace cellmetry {
namespace {

// RMS distance of the points from their mean (mm).
double Spread(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  double sum = 0.0;
  for (const auto& p : points) sum += (p - mean).squaredNorm();
  return std::sqrt(sum / static_cast<double>(points.size()));
}

// Where `file` (a recording.yaml or a robot config) says its length unit, and what it says;
// an empty location when the file cannot tell.
SourceLocation DeclaredLength(const std::string& file, std::string* unit) {
  unit->clear();
  if (file.empty() || !std::filesystem::is_regular_file(file)) return {};
  try {
    const ConfigNode root = ConfigNode::LoadFile(file);
    if (!root.Has("units")) return {file, 0, 0};
    const ConfigNode units = root["units"];
    if (!units.Has("length")) return units.location();
    *unit = units["length"].AsString();
    return units["length"].location();
  } catch (const InputError&) {
    return {file, 0, 0};
  }
}

// Where a camera in a robot cell sees a target: 2 cm to 20 m (mm).
bool PlausibleCameraDistance(double mm) { return mm >= 20.0 && mm <= 2e4; }

[[noreturn]] void Refuse(const WorkcellJob& job, const WorkcellRobot& robot,
                         const Recording& recording, const std::string& target,
                         const std::string& camera, double observed, double flange,
                         double distance) {
  const double ratio = observed / flange;
  const bool larger = ratio > 1.0;
  const double factor = larger ? ratio : 1.0 / ratio;
  const bool thousand = factor > 300.0 && factor < 3000.0;
  char size[32];
  std::snprintf(size, sizeof(size), "%.0f", thousand ? 1000.0 : factor);
  const std::string what = "the recording and robot " + robot.name + " disagree in size by about " +
                           size + " times: target '" + target + "' moves over " + Mm(observed) +
                           " in " + camera + " (RMS about its mean, seen at a median " +
                           Mm(distance) + " from the camera) where " + robot.model_file +
                           " moves the flange over " + Mm(flange) + " at the same joint readings";
  // Which of the two is off: a camera sees targets between 2 cm and 20 m away.
  const bool recording_off = !PlausibleCameraDistance(distance);
  std::string unit;
  SourceLocation where;
  std::string hint;
  if (recording_off) {
    where =
        DeclaredLength(recording.folder.empty() ? "" : recording.folder + "/recording.yaml", &unit);
    const std::string right = larger ? "mm" : "m";
    hint = "A camera does not see its target " + Mm(distance) + " away";
    const bool imported =
        !recording.folder.empty() && std::filesystem::exists(recording.folder + "/import.yaml");
    const std::string looks = std::string(larger ? "millimetres" : "metres");
    if (imported) {
      hint = "This recording was imported (its mapping is in import.yaml): " +
             (thousand ? "the table's lengths look like " + looks +
                             "; say units: {length: " + right + "} in the mapping"
                       : std::string("check units: in the mapping")) +
             " and import it again";
    } else if (thousand && unit != right) {
      hint = "The recording's numbers look like " + looks +
             (unit.empty() ? "" : " but recording.yaml declares length: " + unit) +
             ": declare units: {length: " + right + "}";
    } else {
      hint += ": check units: in recording.yaml";
    }
  } else {
    where = DeclaredLength(robot.model_file, &unit);
    hint = "The recording's distances are plausible, so the robot config's lengths look " +
           std::string(size) + " times too " + (larger ? "small" : "large");
    if (thousand) {
      const std::string right = larger ? "m" : "mm";
      hint += unit.empty() || unit == right
                  ? ": check its numbers and units:"
                  : ": it declares length: " + unit + "; declare units: {length: " + right + "}";
    } else {
      hint += ": check its numbers and units:";
    }
  }
  if (where.file.empty()) where = job.Where("robots." + robot.name);
  throw InputError(where, what, hint);
}

}  // namespace

void CheckLengthScale(const WorkcellJob& job, const Recording& recording) {
  for (const auto& robot : job.problem.robots) {
    std::vector<double> params;
    for (const auto& p : robot.model_parameters) params.push_back(p.nominal);
    std::map<int, Eigen::Vector3d> flange;  // sample id -> nominal flange position (base, mm)
    for (const auto& sample : recording.samples) {
      if (sample.robot != robot.name ||
          static_cast<int>(sample.q.size()) != robot.model->num_joints()) {
        continue;
      }
      Pose T_base_flange;
      if (robot.model->Forward(sample.q.data(), params.data(), &T_base_flange)) {
        flange[sample.id] = T_base_flange.t;
      }
    }
    for (const auto& tool : robot.tools) {
      for (const auto& camera : recording.cameras) {
        std::vector<Eigen::Vector3d> observed, moved;
        std::vector<double> distances;
        for (const auto& o : recording.observations) {
          if (o.target != tool.target || o.camera != camera) continue;
          const auto f = flange.find(o.sample);
          if (f == flange.end()) continue;
          observed.push_back(o.position_mm);
          moved.push_back(f->second);
          distances.push_back(o.position_mm.norm());
        }
        if (observed.size() < 3) continue;
        const double flange_spread = Spread(moved);
        if (flange_spread < 1.0) continue;
        const double ratio = Spread(observed) / flange_spread;
        if (ratio > kLengthScaleLimit || ratio < 1.0 / kLengthScaleLimit) {
          Refuse(job, robot, recording, tool.target, camera, Spread(observed), flange_spread,
                 Median(distances));
        }
      }
    }
  }
}

}  // namespace cellmetry
