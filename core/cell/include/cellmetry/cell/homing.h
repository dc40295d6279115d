// Visual homing: the motors' homing offsets from marker positions measured by the camera, for an
// arm whose geometry and camera pose are known (calibrated once; homing runs at every power-up).
//
// Two estimates side by side:
//  - the report's interval algorithm (Poree 2023, sec. 5.1, fig. 15-16):
//      1. per position k, the measured offset e_k = IK(measured point) - command, per motor;
//      2. its interval e_k +- n_sigma * sd_k, sd_k the measurement noise propagated through the
//         IK Jacobian; positions taken in order of sensitivity (narrowest interval first) and
//         intersected until every motor's interval is narrower than the target width;
//      3. validation rerun: with that offset applied, steps 1-2 again on the positions not used
//         yet; the offset stands if the residual interval holds zero and its middle is under one
//         increment, else the residual is added and the rerun repeats;
//  - weighted least squares over every position, e = (sum W_k)^-1 sum W_k e_k with
//    W_k = (J_k Sigma J_k^T)^-1, and its covariance (sum W_k)^-1: the efficient estimate.
// The geometry error of an uncalibrated arm biases both (homing is not kinematic calibration):
// calibrate first, or free the homing offsets in the kinematic calibration.
#pragma once

#include <string>
#include <vector>

#include <memory>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/transform.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

// What homing knows of the arm: its model at its calibrated values (the homing entries are the
// starting estimate), the camera in its base frame and the marker on its flange.
struct HomingArm {
  std::shared_ptr<const RobotModel> model;
  std::vector<Parameter> model_parameters;  // `nominal` = calibrated value
  Pose T_base_cam;
  Eigen::Vector3d marker_mm = Eigen::Vector3d::Zero();
};

// One measured marker position with the command that produced it.
struct PointSample {
  int sample = 0;              // sample id in the recording
  std::vector<double> q;       // commanded joint values (rad)
  Eigen::Vector3d p_cam_mm;    // measured marker position in the camera frame
  SourceLocation command_at;   // the sample's line in samples.csv (for errors)
  SourceLocation measured_at;  // the observation's line in observations.csv
};

struct HomingOptions {
  double n_sigma = 3.0;                  // interval half-width, in propagated sigma
  double target_width_increments = 1.0;  // stop intersecting when every interval is narrower
  int min_positions = 3;                 // fewer is an input error
  int max_reruns = 3;                    // validation reruns before giving up
};

struct HomingRun {
  std::vector<int> samples;              // sample ids used, in the order they were intersected
  Eigen::Vector3d lower_rad, upper_rad;  // final interval per motor (of the residual, on reruns)
  std::vector<int> rejected;             // positions whose interval missed the intersection
};

struct HomingResult {
  double increment_rad = 0.0;  // one motor increment (0 if the model has none)
  Eigen::Vector3d interval_offset_rad = Eigen::Vector3d::Zero();  // the interval algorithm
  Eigen::Vector3d interval_width_rad = Eigen::Vector3d::Zero();   // of the first run
  std::vector<HomingRun> runs;  // first run, then validation reruns
  bool validated = false;
  std::string validation;                                    // one line: how the validation went
  Eigen::Vector3d lsq_offset_rad = Eigen::Vector3d::Zero();  // least squares
  Eigen::Vector3d lsq_sigma_rad = Eigen::Vector3d::Zero();
  int positions = 0;  // usable positions in the recording
  std::vector<std::string> warnings;
};

// `sigma_mm`: the measurement noise along camera x, y, depth.
HomingResult HomeVisually(const HomingArm& arm, const std::vector<PointSample>& samples,
                          const Eigen::Vector3d& sigma_mm, const HomingOptions& options);

// In motor increments (rad if the model has no increment).
double InIncrements(double rad, double increment_rad);

}  // namespace cellmetry
