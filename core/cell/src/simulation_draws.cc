// Random draws of a simulation (simulation_draws.h): the truth around the nominal cell, pose sets.
#include "cellmetry/cell/simulation_draws.h"

#include <cmath>

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

Eigen::Vector3d InCylinder(const CylinderWorkspace& w, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double radius = w.radius_mm * std::sqrt(u(rng)), angle = 2 * M_PI * u(rng);
  return {radius * std::cos(angle), radius * std::sin(angle),
          w.z_min_mm + (w.z_max_mm - w.z_min_mm) * u(rng)};
}

Eigen::Vector3d OnCylinder(const CylinderWorkspace& w, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double side = 2 * M_PI * w.radius_mm * (w.z_max_mm - w.z_min_mm);
  const double disk = M_PI * w.radius_mm * w.radius_mm;
  const double pick = u(rng) * (side + 2 * disk);
  if (pick < side) {
    const double angle = 2 * M_PI * u(rng);
    return {w.radius_mm * std::cos(angle), w.radius_mm * std::sin(angle),
            w.z_min_mm + (w.z_max_mm - w.z_min_mm) * u(rng)};
  }
  Eigen::Vector3d p = InCylinder(w, rng);
  p.z() = pick < side + disk ? w.z_min_mm : w.z_max_mm;
  return p;
}

bool InView(const PoseSetGeometry& g, const Eigen::Vector3d& marker_base) {
  return InFieldOfView(g.half_fov_rad, g.T_base_cam.inverse() * marker_base);
}

double Uniform(std::mt19937& rng, double half_width) {
  return std::uniform_real_distribution<double>(-half_width, half_width)(rng);
}

}  // namespace

bool InFieldOfView(const Eigen::Vector2d& half_fov_rad, const Eigen::Vector3d& p_cam) {
  return p_cam.z() > 0 && std::abs(p_cam.x()) < p_cam.z() * std::tan(half_fov_rad.x()) &&
         std::abs(p_cam.y()) < p_cam.z() * std::tan(half_fov_rad.y());
}

std::string PoseSetName(PoseSet set) {
  switch (set) {
    case PoseSet::kCameraView: return "camera_view";
    case PoseSet::kUniformWorkspace: return "uniform_workspace";
    case PoseSet::kBoundaries: return "boundaries";
  }
  return "";
}

PoseSet ParsePoseSet(const ConfigNode& node) {
  const std::string name = node.AsString();
  for (PoseSet set : {PoseSet::kCameraView, PoseSet::kUniformWorkspace, PoseSet::kBoundaries}) {
    if (name == PoseSetName(set)) return set;
  }
  const std::string nearest = NearestWord(name, {"camera_view", "uniform_workspace", "boundaries"});
  throw node.Error("unknown pose set '" + name + "'",
                   (nearest.empty() ? "" : "Did you mean '" + nearest + "'? ") +
                       "Use camera_view, uniform_workspace or boundaries");
}

std::vector<double> DrawModelTruth(const RobotModel& model, const std::vector<double>& nominal,
                                   const ModelErrors& errors, std::mt19937& rng) {
  std::vector<double> truth = nominal;
  const double increment = model.limits().joint_increment_rad;
  const auto& params = model.parameters();
  for (size_t i = 0; i < params.size(); ++i) {
    if (params[i].unit == "mm") {
      truth[i] += Uniform(rng, errors.dimensions_mm);
    } else if (params[i].unit == "rad") {
      truth[i] += Uniform(rng, errors.homing_increments * increment);
    }
  }
  return truth;
}

Pose DrawCameraTruth(const Pose& nominal, const CameraErrors& errors, std::mt19937& rng) {
  Eigen::Vector3d rvec, shift;
  for (int k = 0; k < 3; ++k) {
    rvec[k] = Uniform(rng, errors.rad);
    shift[k] = Uniform(rng, errors.mm);
  }
  return Pose{RotationFromRvec(rvec.data()) * nominal.R, nominal.t + shift};
}

std::vector<std::vector<double>> DrawPoseSet(const PoseSetGeometry& g, PoseSet set, int count,
                                             std::mt19937& rng) {
  if (!g.model->limits().workspace) {
    throw InputError({g.origin, 0, 0}, "the robot config has no workspace",
                     "Add workspace: {radius, z_min, z_max} to the robot config");
  }
  if (set == PoseSet::kCameraView && !g.camera_known) {
    throw InputError({g.origin, 0, 0}, "the camera_view pose set names no camera",
                     "Give poses: {set: camera_view, camera: <name>}");
  }
  const CylinderWorkspace& w = *g.model->limits().workspace;
  std::vector<std::vector<double>> commands;
  for (int attempts = 0; static_cast<int>(commands.size()) < count; ++attempts) {
    if (attempts > 1000 * count) {
      throw InputError({g.origin, 0, 0},
                       "the pose set '" + PoseSetName(set) + "' has no reachable point in view",
                       "Check the workspace against the camera pose and field of view");
    }
    const Eigen::Vector3d flange =
        set == PoseSet::kBoundaries ? OnCylinder(w, rng) : InCylinder(w, rng);
    if (set == PoseSet::kCameraView && !InView(g, flange + g.marker_mm)) continue;
    std::vector<double> q(g.model->num_joints());
    if (!g.model->Inverse(flange.data(), g.nominal_values.data(), q.data())) continue;
    commands.push_back(q);
  }
  return commands;
}

}  // namespace cellmetry
