// Closed-form starting values (workcell_initial.h), step by step.
#include "cellmetry/cell/workcell_initial.h"

#include <Eigen/Dense>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/rigid_fit.h"

namespace cellmetry {
namespace {

Pose Observed(const Observation& obs) {
  return Pose{obs.rvec ? RotationFromRvec(obs.rvec->data()) : Eigen::Matrix3d::Identity(),
              obs.position_mm};
}

// Static cameras that see the world target: inverse of their mean world-target pose.
void InitialCameras(const WorkcellProblem& spec, const Recording& recording,
                    const WorkcellData& data, WorkcellEstimate* estimate) {
  std::map<std::string, std::vector<Pose>> seen;
  for (int index : data.world_observations) {
    const Observation& obs = recording.observations[index];
    seen[obs.camera].push_back(Observed(obs));
  }
  for (const auto& [camera, poses] : seen) {
    std::vector<Eigen::Matrix3d> rotations;
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    for (const auto& p : poses) {
      rotations.push_back(p.R);
      t += p.t;
    }
    const Pose T_cam_world{MeanRotation(rotations), t / static_cast<double>(poses.size())};
    estimate->T_world_cam[camera] = T_cam_world.inverse();
  }
}

struct RobotPoint {
  Pose T_base_flange;
  Eigen::Vector3d p_world;
  Eigen::Matrix3d R_world_target;
  int tool = 0;
};

// Alternates Kabsch (rotation + translation) with a linear solve for translations.
void InitialBaseAndTools(const WorkcellRobot& robot, const std::vector<RobotPoint>& points,
                         WorkcellEstimate* estimate) {
  std::vector<Eigen::Vector3d> tool_t;
  for (const auto& tool : robot.tools) tool_t.push_back(estimate->T_flange_target[tool.target].t);
  Pose T_world_base = robot.base_start ? *robot.base_start : Pose::Identity();
  std::vector<Eigen::Vector3d> world;
  for (const auto& p : points) world.push_back(p.p_world);

  for (int round = 0; round < 50; ++round) {
    if (!robot.base_start) {
      std::vector<Eigen::Vector3d> in_base;
      for (const auto& p : points) in_base.push_back(p.T_base_flange * tool_t[p.tool]);
      const auto fit = FitRigidTransform(in_base, world);
      if (!fit) break;
      T_world_base = *fit;
    }
    // Unknowns: base translation (3, when it is free or not given) and free tool translations.
    std::vector<std::pair<int, int>> columns;  // (-1, axis) base; (tool, axis) tool
    for (int a = 0; a < 3; ++a) {
      if (!robot.base_start) columns.push_back({-1, a});
    }
    for (size_t t = 0; t < robot.tools.size(); ++t) {
      for (int a = 0; a < 3; ++a) {
        if (robot.tools[t].flange_tool.free[a]) columns.push_back({static_cast<int>(t), a});
      }
    }
    if (columns.empty()) break;
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * points.size(), columns.size());
    Eigen::VectorXd b(3 * points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      const auto& p = points[i];
      const Eigen::Matrix3d R_world_flange = T_world_base.R * p.T_base_flange.R;
      Eigen::Vector3d rhs = p.p_world - T_world_base.R * p.T_base_flange.t;
      if (robot.base_start) rhs -= T_world_base.t;
      for (size_t c = 0; c < columns.size(); ++c) {
        const auto [tool, axis] = columns[c];
        if (tool < 0) {
          A(3 * i + axis, c) = 1.0;
        } else if (tool == p.tool) {
          A.block<3, 1>(3 * i, c) = R_world_flange.col(axis);
        }
      }
      // Fixed tool translation components are known: move them to the right-hand side.
      for (int a = 0; a < 3; ++a) {
        if (!robot.tools[p.tool].flange_tool.free[a]) {
          rhs -= R_world_flange.col(a) * tool_t[p.tool][a];
        }
      }
      b.segment<3>(3 * i) = rhs;
    }
    // Minimum norm: where the poses cannot separate base and tool translations (a delta's
    // flange never turns, so only their sum is seen), neither runs off to 1e12 mm; the fit's
    // identifiability check then says which to hold.
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
    svd.setThreshold(1e-9);
    const Eigen::VectorXd x = svd.solve(b);
    double change = 0.0;
    for (size_t c = 0; c < columns.size(); ++c) {
      const auto [tool, axis] = columns[c];
      double& value = tool < 0 ? T_world_base.t[axis] : tool_t[tool][axis];
      change = std::max(change, std::abs(value - x[c]));
      value = x[c];
    }
    if (change < 1e-9) break;
  }
  estimate->T_world_base[robot.name] = T_world_base;
  for (size_t t = 0; t < robot.tools.size(); ++t) {
    estimate->T_flange_target[robot.tools[t].target].t = tool_t[t];
  }
}

// Step 2's input: every carried-target measurement whose camera is placed, in the world frame.
std::vector<std::vector<RobotPoint>> WorldPoints(const WorkcellProblem& spec,
                                                 const Recording& recording,
                                                 const WorkcellData& data,
                                                 const WorkcellEstimate& estimate) {
  const bool static_cameras = spec.camera_model == CameraModel::kStaticCameras;
  std::vector<std::vector<RobotPoint>> points(spec.robots.size());
  for (const ToolMeasurement& m : data.tools) {
    const Observation& obs = recording.observations[m.observation];
    Pose T_world_cam;
    if (static_cameras) {
      const auto camera = estimate.T_world_cam.find(obs.camera);
      if (camera == estimate.T_world_cam.end()) continue;  // located later through the robot
      T_world_cam = camera->second;
    } else {
      T_world_cam = m.T_cam_world.inverse();
    }
    const WorkcellRobot& robot = spec.robots[m.robot];
    RobotPoint point;
    if (!robot.model->Forward(recording.samples[m.sample_index].q.data(),
                              estimate.model.at(robot.name).data(), &point.T_base_flange)) {
      continue;
    }
    point.p_world = T_world_cam * obs.position_mm;
    point.R_world_target = T_world_cam.R * Observed(obs).R;
    point.tool = m.tool;
    points[m.robot].push_back(point);
  }
  return points;
}

// Step 3: each tool's rotation as the chordal mean over its captures.
void InitialToolRotations(const WorkcellRobot& robot, const std::vector<RobotPoint>& points,
                          WorkcellEstimate* estimate) {
  for (size_t t = 0; t < robot.tools.size(); ++t) {
    std::vector<Eigen::Matrix3d> rotations;
    for (const auto& p : points) {
      if (p.tool != static_cast<int>(t)) continue;
      rotations.push_back((estimate->T_world_base[robot.name].R * p.T_base_flange.R).transpose() *
                          p.R_world_target);
    }
    if (!rotations.empty()) {
      estimate->T_flange_target[robot.tools[t].target].R = MeanRotation(rotations);
    }
  }
}

// Step 4: static cameras that never saw the world target, located through the robots.
void CamerasThroughRobots(const WorkcellProblem& spec, const Recording& recording,
                          const WorkcellData& data, WorkcellEstimate* estimate) {
  std::map<std::string, std::pair<std::vector<Eigen::Vector3d>, std::vector<Eigen::Vector3d>>>
      matches;
  for (const ToolMeasurement& m : data.tools) {
    const Observation& obs = recording.observations[m.observation];
    if (estimate->T_world_cam.count(obs.camera)) continue;
    const WorkcellRobot& robot = spec.robots[m.robot];
    Pose T_base_flange;
    if (!robot.model->Forward(recording.samples[m.sample_index].q.data(),
                              estimate->model[robot.name].data(), &T_base_flange)) {
      continue;
    }
    const Eigen::Vector3d p_world = estimate->T_world_base[robot.name] * T_base_flange *
                                    estimate->T_flange_target[robot.tools[m.tool].target].t;
    matches[obs.camera].first.push_back(obs.position_mm);
    matches[obs.camera].second.push_back(p_world);
  }
  for (const auto& [camera, pairs] : matches) {
    const auto fit = FitRigidTransform(pairs.first, pairs.second);
    if (!fit) {
      throw InputError({recording.folder + "/observations.csv", 0, 0},
                       "camera '" + camera + "' never sees the world target and sees robot "
                       "targets at fewer than 3 non-collinear places",
                       "Let the camera see the world target, or record more poses in its view");
    }
    estimate->T_world_cam[camera] = *fit;
  }
}

}  // namespace

WorkcellEstimate InitialEstimate(const WorkcellProblem& spec, const Recording& recording,
                                 const WorkcellData& data) {
  WorkcellEstimate estimate;
  const bool static_cameras = spec.camera_model == CameraModel::kStaticCameras;
  if (static_cameras) {
    InitialCameras(spec, recording, data, &estimate);
    for (const auto& [camera, given] : spec.cameras) {
      if (given.start) estimate.T_world_cam[camera] = *given.start;
    }
  }
  for (const auto& robot : spec.robots) {
    std::vector<double> nominal;
    for (const auto& p : robot.model_parameters) nominal.push_back(p.nominal);
    estimate.model[robot.name] = nominal;
    for (const auto& tool : robot.tools) estimate.T_flange_target[tool.target] = tool.flange_tool.start;
  }
  const auto points = WorldPoints(spec, recording, data, estimate);
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    const WorkcellRobot& robot = spec.robots[r];
    if (points[r].size() < 3 && !robot.base_start) {
      throw InputError({recording.folder + "/observations.csv", 0, 0},
                       "robot '" + robot.name + "' has " + std::to_string(points[r].size()) +
                           " usable measurements in the world frame; at least 3 are needed",
                       "Record more poses where a camera sees both the world target and the "
                       "robot's target");
    }
    InitialBaseAndTools(robot, points[r], &estimate);
    if (spec.use_tool_rotation) InitialToolRotations(robot, points[r], &estimate);
  }
  if (static_cameras) CamerasThroughRobots(spec, recording, data, &estimate);
  return estimate;
}

}  // namespace cellmetry
