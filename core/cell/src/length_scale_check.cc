// CheckLengthScale (length_scale_check.h): the observed motion of each carried target against
// the robot config's motion of the flange, at the same joint readings.
#include "length_scale_check.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <vector>

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

std::string Mm(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g mm", value);
  return text;
}

// Where the recording says its length unit, and what it says ("" when not from a folder).
SourceLocation DeclaredLength(const Recording& recording, std::string* unit) {
  unit->clear();
  if (recording.folder.empty()) return {};
  const std::string header = recording.folder + "/recording.yaml";
  try {
    const ConfigNode root = ConfigNode::LoadFile(header);
    const ConfigNode units = root["units"];
    if (units.Has("length")) {
      *unit = units["length"].AsString();
      return units["length"].location();
    }
    return units.location();
  } catch (const InputError&) {
    return {header, 0, 0};
  }
}

[[noreturn]] void Refuse(const WorkcellJob& job, const WorkcellRobot& robot,
                         const Recording& recording, const std::string& target,
                         const std::string& camera, double observed, double flange) {
  const double ratio = observed / flange;
  std::string unit;
  SourceLocation where = DeclaredLength(recording, &unit);
  if (where.file.empty()) where = job.Where("robots." + robot.name);
  const bool larger = ratio > 1.0;
  const double factor = larger ? ratio : 1.0 / ratio;
  const bool thousand = factor > 300.0 && factor < 3000.0;
  char size[32];
  std::snprintf(size, sizeof(size), "%.0f", thousand ? 1000.0 : factor);
  const std::string what =
      "the recording's lengths are about " + std::string(size) + " times too " +
      (larger ? "large" : "small") + " for robot '" + robot.name + "': target '" + target +
      "' moves over " + Mm(observed) + " in " + camera + " (RMS about its mean) where " +
      robot.model_file + " moves the flange over " + Mm(flange) + " at the same joint readings";
  const std::string right = larger ? "mm" : "m";
  std::string hint = "Check units: in recording.yaml";
  if (thousand && unit != right) {
    hint = std::string("Its numbers look like ") + (larger ? "millimetres" : "metres") +
           (unit.empty() ? "" : " but recording.yaml declares length: " + unit) +
           ": declare units: {length: " + right + "}";
  }
  if (!recording.folder.empty() &&
      std::filesystem::exists(recording.folder + "/import.yaml")) {
    hint += "; this recording was imported (import.yaml): fix units: in its mapping and import "
            "it again";
  }
  hint += "; or check the units of the robot config " + robot.model_file;
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
        for (const auto& o : recording.observations) {
          if (o.target != tool.target || o.camera != camera) continue;
          const auto f = flange.find(o.sample);
          if (f == flange.end()) continue;
          observed.push_back(o.position_mm);
          moved.push_back(f->second);
        }
        if (observed.size() < 3) continue;
        const double flange_spread = Spread(moved);
        if (flange_spread < 1.0) continue;
        const double ratio = Spread(observed) / flange_spread;
        if (ratio > kLengthScaleLimit || ratio < 1.0 / kLengthScaleLimit) {
          Refuse(job, robot, recording, tool.target, camera, Spread(observed), flange_spread);
        }
      }
    }
  }
}

}  // namespace cellmetry
