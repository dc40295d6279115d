// Closed-form starting values (workcell_initial.h), step by step.
#include "cellmetry/cell/workcell_initial.h"

#include <Eigen/Dense>

#include "cellmetry/basics/dense_decompositions.h"
#include "cellmetry/basics/error.h"
#include "cellmetry/basics/rigid_fit.h"
#include "base_fit_sums.h"
#include "hand_eye_start.h"

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

// The linear step of InitialBaseAndTools: base translation (when free or not given) and free
// tool translations, least squares with minimum norm (where the poses cannot separate base and
// tool translations, as on a delta whose flange never turns, neither runs off to 1e12 mm; the
// fit's identifiability check then says which to hold).
//
// Point i's rows are [I | R_world_base R_base_flange_i S] (S: the free tool axes). With the base
// translation's unknown taken as R_world_base^T t (an orthogonal change of unknowns: same
// residuals, same norms, same singular values) they are [I | R_base_flange_i S], which no round
// changes: the matrix is factored once (QR, then an SVD of its small R with the old 1e-9
// threshold) and each round only rotates the right-hand side. The SVD of the whole 3N x 6
// matrix in every one of ~45 rounds was most of exp_a's closed-form start.
//
// A run of n points at one flange pose (FlangeRunStarts) has n equal rows: it is one row block
// sqrt(n) [I | R_base_flange S] against the right-hand side sum_i b_i / sqrt(n), which has the
// same normal equations (so the same solution and singular values) and leaves exp_a 250 row
// blocks to factor instead of 7,500.
class TranslationStep {
 public:
  TranslationStep(const WorkcellRobot& robot, const std::vector<RobotPoint>& points,
                  const std::vector<size_t>& run_starts) {
    for (int a = 0; a < 3; ++a) {
      if (!robot.base_start) columns_.push_back({-1, a});
    }
    for (size_t t = 0; t < robot.tools.size(); ++t) {
      for (int a = 0; a < 3; ++a) {
        // A camera on the flange is placed by hand_eye_start.h, not by target points.
        if (robot.tools[t].flange_tool.free[a] && !robot.tools[t].is_camera()) {
          columns_.push_back({static_cast<int>(t), a});
        }
      }
    }
    const size_t runs = run_starts.size() - 1;
    A_ = Eigen::MatrixXd::Zero(3 * runs, columns_.size());
    for (size_t run = 0; run < runs; ++run) {
      const RobotPoint& p = points[run_starts[run]];
      const double weight = std::sqrt(static_cast<double>(run_starts[run + 1] - run_starts[run]));
      for (size_t c = 0; c < columns_.size(); ++c) {
        const auto [tool, axis] = columns_[c];
        if (tool < 0) {
          A_(3 * run + axis, c) = weight;
        } else if (tool == p.tool) {
          A_.block<3, 1>(3 * run, c) = weight * p.T_base_flange.R.col(axis);
        }
      }
    }
    if (columns_.empty()) return;  // nothing to solve for: the rounds stop at once
    if (A_.rows() >= A_.cols()) {
      qr_.compute(A_);
      const Eigen::MatrixXd R = qr_.matrixQR().topRows(A_.cols()).triangularView<Eigen::Upper>();
      svd_.compute(R, Eigen::ComputeThinU | Eigen::ComputeThinV);
    } else {
      svd_.compute(A_, Eigen::ComputeThinU | Eigen::ComputeThinV);
    }
    svd_.setThreshold(1e-9);
  }

  const std::vector<std::pair<int, int>>& columns() const { return columns_; }

  // The minimum-norm solution for each right-hand side, a column of `b` (rows as A's: a run's
  // sum over its points divided by sqrt(n)), base part in the base's rotated frame.
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& b) const {
    if (A_.rows() < A_.cols()) return svd_.solve(b);
    const Eigen::MatrixXd Qt_b = qr_.householderQ().transpose() * b;
    return svd_.solve(Qt_b.topRows(A_.cols()));
  }

 private:
  std::vector<std::pair<int, int>> columns_;  // (-1, axis) base; (tool, axis) tool
  Eigen::MatrixXd A_;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr_;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd_;
};

// The linear step's right-hand sides, for any base rotation: point i's rows are what remains of
// R_wb^T p_world once the flange position (and a given base translation, and the held tool
// translation components) are taken away, linear in the nine entries of R_bw = R_wb^T. Column
// 3a + c holds the coefficients of R_bw(a, c), column 9 the rest: the rounds then solve
// once, here, and combine the solutions. Rows per run of points at one flange pose, as the
// TranslationStep's.
Eigen::MatrixXd TranslationRhsColumns(const WorkcellRobot& robot,
                                      const std::vector<RobotPoint>& points,
                                      const std::vector<size_t>& run_starts,
                                      const std::vector<Eigen::Vector3d>& tool_t) {
  const size_t runs = run_starts.size() - 1;
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(3 * runs, 10);
  for (size_t run = 0; run < runs; ++run) {
    const double n = static_cast<double>(run_starts[run + 1] - run_starts[run]);
    Eigen::Vector3d world = Eigen::Vector3d::Zero();
    for (size_t i = run_starts[run]; i < run_starts[run + 1]; ++i) {
      world += robot.base_start ? Eigen::Vector3d(points[i].p_world - robot.base_start->t)
                                : points[i].p_world;
    }
    const RobotPoint& p = points[run_starts[run]];
    Eigen::Vector3d rest = -p.T_base_flange.t;
    for (int a = 0; a < 3; ++a) {
      if (!robot.tools[p.tool].flange_tool.free[a]) {
        rest -= p.T_base_flange.R.col(a) * tool_t[p.tool][a];
      }
    }
    // sum_i b_i / sqrt(n): the world part summed, the flange part n times.
    world /= std::sqrt(n);
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 3; ++c) b(3 * run + a, 3 * a + c) = world[c];
    }
    b.block<3, 1>(3 * run, 9) = std::sqrt(n) * rest;
  }
  return b;
}

// Base pose and free translations by alternating the two least-squares steps (base_fit_sums.h)
// until they agree to 1e-9 mm (about 45 rounds on exp_a; each costs a 3 x 3 SVD).
void InitialBaseAndTools(const WorkcellRobot& robot, const std::vector<RobotPoint>& points,
                         WorkcellEstimate* estimate) {
  std::vector<Eigen::Vector3d> tool_t;
  for (const auto& tool : robot.tools) tool_t.push_back(estimate->T_flange_target[tool.target].t);
  Pose T_world_base = robot.base_start ? *robot.base_start : Pose::Identity();
  const std::vector<size_t> run_starts = FlangeRunStarts(points);
  const TranslationStep step(robot, points, run_starts);
  const BaseFitSums base_fit(points, static_cast<int>(robot.tools.size()));
  const Eigen::MatrixXd solutions =
      step.columns().empty() ? Eigen::MatrixXd()
                             : step.Solve(TranslationRhsColumns(robot, points, run_starts, tool_t));

  for (int round = 0; round < 50; ++round) {
    if (!robot.base_start) {
      const auto fit = base_fit.Fit(tool_t);
      if (!fit) break;
      T_world_base = *fit;
    }
    if (step.columns().empty()) break;
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> R_bw = T_world_base.R.transpose();
    const Eigen::VectorXd x =
        solutions.leftCols<9>() * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(R_bw.data()) +
        solutions.col(9);
    // The base's unknown was R_world_base^T t: back in the world frame.
    const Eigen::Vector3d base_t =
        robot.base_start ? T_world_base.t : Eigen::Vector3d(T_world_base.R * x.head<3>());
    double change = 0.0;
    for (size_t c = 0; c < step.columns().size(); ++c) {
      const auto [tool, axis] = step.columns()[c];
      double& value = tool < 0 ? T_world_base.t[axis] : tool_t[tool][axis];
      const double solved = tool < 0 ? base_t[axis] : x[c];
      change = std::max(change, std::abs(value - solved));
      value = solved;
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
  // The measurements of one capture, and the repeated captures of one pose, follow each other
  // at the same joints: their chain is run once (exp_a: 7,500 measurements, 250 poses).
  const std::vector<double>* last_q = nullptr;
  int last_robot = -1;
  bool last_ok = false;
  Pose last_T_base_flange;
  for (const ToolMeasurement& m : data.tools) {
    if (spec.robots[m.robot].tools[m.tool].is_camera()) continue;  // eye in hand: no point
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
    const std::vector<double>& q = recording.samples[m.sample_index].q;
    if (m.robot != last_robot || last_q == nullptr || q != *last_q) {
      last_ok =
          robot.model->Forward(q.data(), estimate.model.at(robot.name).data(), &last_T_base_flange);
      last_q = &q;
      last_robot = m.robot;
    }
    if (!last_ok) continue;
    RobotPoint point;
    point.T_base_flange = last_T_base_flange;
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
    if (spec.robots[m.robot].tools[m.tool].is_camera()) continue;  // eye in hand: it moves
    const Observation& obs = recording.observations[m.observation];
    if (estimate->T_world_cam.count(obs.camera)) continue;
    const WorkcellRobot& robot = spec.robots[m.robot];
    if (!estimate->T_world_base.count(robot.name)) continue;  // placed through the cameras later
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
                       "camera '" + camera +
                           "' never sees the world target and sees robot "
                           "targets at fewer than 3 non-collinear places",
                       "Let the camera see the world target, or record more poses in its view");
    }
    estimate->T_world_cam[camera] = *fit;
  }
}

// A cell whose cameras see no world target and whose robots stand where the job puts them (the
// eye-to-hand cell: one static camera, a board on the tool): the cameras were placed through the
// robots with the tools at their nominal offsets. The tools' offsets and the cameras' poses are
// then solved in turn, each in closed form given the other (the tools by InitialBaseAndTools
// with the base held, the cameras by a rigid fit), until the tools move by less than a micron.
void ToolsAndCamerasInTurn(const WorkcellProblem& spec, const Recording& recording,
                           const WorkcellData& data, const std::vector<size_t>& robots,
                           WorkcellEstimate* estimate) {
  std::set<std::string> placed_through_robots;
  for (const auto& [camera, pose] : estimate->T_world_cam) {
    const auto given = spec.cameras.find(camera);
    if (given == spec.cameras.end() || !given->second.start) placed_through_robots.insert(camera);
  }
  for (int round = 0; round < 100; ++round) {
    const auto points = WorldPoints(spec, recording, data, *estimate);
    double moved = 0.0;
    for (size_t r : robots) {
      const WorkcellRobot& robot = spec.robots[r];
      if (points[r].size() < 3) continue;
      std::vector<Eigen::Vector3d> before;
      for (const auto& tool : robot.tools)
        before.push_back(estimate->T_flange_target[tool.target].t);
      InitialBaseAndTools(robot, points[r], estimate);
      if (spec.use_tool_rotation) InitialToolRotations(robot, points[r], estimate);
      for (size_t t = 0; t < robot.tools.size(); ++t) {
        moved = std::max(moved,
                         (estimate->T_flange_target[robot.tools[t].target].t - before[t]).norm());
      }
    }
    for (const auto& camera : placed_through_robots) estimate->T_world_cam.erase(camera);
    CamerasThroughRobots(spec, recording, data, estimate);
    if (moved < 1e-3) break;
  }
}

InputError NotInTheWorld(const WorkcellRobot& robot, size_t points, const Recording& recording) {
  return InputError({recording.folder + "/observations.csv", 0, 0},
                    "robot '" + robot.name + "' has " + std::to_string(points) +
                        " usable measurements in the world frame; at least 3 are needed",
                    "Record more poses where a camera sees both the world target (or, without "
                    "one, the first robot's target) and this robot's target");
}

// Robots that stand where no world target places them and no start puts them (the second and
// later robots of a cell without a world target), placed through the cameras the first robot
// placed: their targets' world points, then their base and tools in closed form.
void PlaceThroughCameras(const WorkcellProblem& spec, const Recording& recording,
                         const WorkcellData& data, const std::vector<size_t>& robots,
                         WorkcellEstimate* estimate) {
  const auto points = WorldPoints(spec, recording, data, *estimate);
  for (size_t r : robots) {
    const WorkcellRobot& robot = spec.robots[r];
    if (points[r].size() < 3) throw NotInTheWorld(robot, points[r].size(), recording);
    InitialBaseAndTools(robot, points[r], estimate);
    if (spec.use_tool_rotation) InitialToolRotations(robot, points[r], estimate);
  }
}

// Whether `start` places every robot (base and model), tool and static camera `data` uses.
bool PlacesEverything(const WorkcellEstimate& start, const WorkcellProblem& spec,
                      const Recording& recording, const WorkcellData& data) {
  for (const auto& robot : spec.robots) {
    if (!start.T_world_base.count(robot.name) || !start.model.count(robot.name)) return false;
    for (const auto& tool : robot.tools) {
      if (!start.T_flange_target.count(tool.target)) return false;
    }
  }
  if (spec.camera_model != CameraModel::kStaticCameras) return true;
  std::vector<int> used;
  for (const ToolMeasurement& m : data.tools) used.push_back(m.observation);
  used.insert(used.end(), data.world_observations.begin(), data.world_observations.end());
  for (int i : used) {
    if (!start.T_world_cam.count(recording.observations[i].camera)) return false;
  }
  return true;
}

}  // namespace

WorkcellEstimate InitialEstimate(const WorkcellProblem& spec, const Recording& recording,
                                 const WorkcellData& data) {
  if (spec.warm_start && PlacesEverything(*spec.warm_start, spec, recording, data)) {
    return *spec.warm_start;
  }
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
    for (const auto& tool : robot.tools) {
      estimate.T_flange_target[tool.target] = tool.flange_tool.start;
    }
  }
  HandEyeStart(spec, recording, data, &estimate);
  const auto points = WorldPoints(spec, recording, data, estimate);
  std::vector<size_t> through_cameras;  // robots placed where they stand, seen by no placed camera
  std::vector<size_t> later;            // robots placed through cameras those robots place
  for (size_t r = 0; r < spec.robots.size(); ++r) {
    const WorkcellRobot& robot = spec.robots[r];
    // Placed by the camera riding on it (eye in hand), with no target of its own seen.
    if (points[r].size() < 3 && estimate.T_world_base.count(robot.name)) continue;
    if (points[r].size() < 3 && !robot.base_start) {
      const bool placed_in_turn = spec.world_target.empty() && static_cameras && r > 0;
      if (placed_in_turn) {
        later.push_back(r);
        continue;
      }
      throw NotInTheWorld(robot, points[r].size(), recording);
    }
    if (points[r].size() < 3) {
      estimate.T_world_base[robot.name] = *robot.base_start;
      through_cameras.push_back(r);
      continue;
    }
    InitialBaseAndTools(robot, points[r], &estimate);
    if (spec.use_tool_rotation) InitialToolRotations(robot, points[r], &estimate);
  }
  if (static_cameras) CamerasThroughRobots(spec, recording, data, &estimate);
  if (static_cameras && !through_cameras.empty()) {
    ToolsAndCamerasInTurn(spec, recording, data, through_cameras, &estimate);
  }
  if (!later.empty()) PlaceThroughCameras(spec, recording, data, later, &estimate);
  return estimate;
}

}  // namespace cellmetry
