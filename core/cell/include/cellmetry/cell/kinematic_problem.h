// KinematicProblem: calibrate a robot's kinematics from positions of a marker it carries, as
// seen by one camera that measures points (a stereo camera triangulating a dot). The 2023 delta
// report's setting; any robot model works, and the joint-space formulation needs one with
// position inverse kinematics (robot_model.h).
//
// Unknowns: T_base_cam (the camera in the robot's base frame, 6), the marker offset on the flange
// (3), any robot-model parameter (for a delta arm: R, r, L, l and the homing offset per arm).
// A free camera translation and the marker offset are the same thing for a flange that only
// translates, so the marker is held by default.
//
// Formulations (Poree 2023, sec. 6.1), the same maximum-likelihood problem either way:
//  - forward (Cartesian): r = (T_cam_base * FK(q) * marker - p_measured) / sigma, in camera axes;
//  - inverse (joint space): r = W (IK(T_base_cam * p_measured - marker) - q_command), where W
//    whitens the joint residual by the measurement covariance propagated through the IK Jacobian
//    at the start (W^T W = (J Sigma J^T)^-1), so both formulations weigh the data alike. The
//    report weighted all joint errors equally, which over-trusts samples where the IK is sensitive.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/parameter.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

enum class Formulation { kForward, kInverse };
std::string FormulationName(Formulation formulation);

struct KinematicProblem {
  std::string robot;                          // names in the recording
  std::string target;
  std::string camera;
  std::shared_ptr<const RobotModel> model;
  std::vector<Parameter> model_parameters;    // nominal values start the fit; `fixed` per job

  std::optional<Pose> T_base_cam_start;       // none: closed form (Kabsch on positions)
  std::array<bool, 6> camera_free = {true, true, true, true, true, true};  // x y z rx ry rz
  Eigen::Vector3d marker_mm = Eigen::Vector3d::Zero();  // on the flange (model's nominal tool)
  bool marker_free = false;

  Formulation formulation = Formulation::kForward;
  // Measurement sigma along camera x, y and depth (mm). None: estimated from a first fit's
  // residuals, then refit.
  std::optional<Eigen::Vector3d> sigma_mm;
  double identifiability_tolerance = 1e-8;   // relative singular value of the scaled Jacobian
  // Variance inflation above which a parameter is reported as weakly identified. A delta arm
  // calibrated on a spread pose set shows at most ~1e4 (its parameters are coupled); all
  // positions at one height give ~2e5 for the rod lengths, homing offsets and camera z.
  double weak_vif = 1e5;
};

// One measured marker position with the command that produced it.
struct PointSample {
  int sample = 0;                 // sample id in the recording
  int observation = 0;            // observation index in the recording
  std::vector<double> q;          // commanded joint values (rad)
  Eigen::Vector3d p_cam_mm;       // measured marker position in the camera frame
  SourceLocation command_at;      // the sample's line in samples.csv (for errors)
  SourceLocation measured_at;     // the observation's line in observations.csv
};

}  // namespace cellmetry
