// NoiseModel: the sigma every residual row is divided by.
//
// Per camera and target, along the camera's x, y and depth axes (positions, mm) and about them
// (rotations, rad). Where the job does not give sigma:
//   - observations measured by `cellmetry detect` carry their covariance (position and
//     rotation): sigma is the RMS of their standard deviations, but never below the scatter of
//     repeated captures. A world-fixed target's captures show a camera one view again and again:
//     the detector's systematic error repeats, so together they count as one capture (sigma
//     times sqrt(captures)), and a static camera's pose is not claimed better than one
//     detection can place it;
//   - else it is estimated from repeated captures: captures of one commanded pose (same `pose`)
//     for robot-carried targets, every capture for world-fixed targets; the pooled standard
//     deviation over groups is used;
//   - else sigma is left unknown and the workcell identification estimates it from the
//     residuals of a first fit (variance component estimation).
// A camera the job names in `per_row` (an instrument reporting each reading's own uncertainty:
// a laser tracker's U(95) per row) weighs every row by its own position covariance plus what the
// model leaves out of every row alike, sigma_row^2 = sigma^2 + diag(C_row): sigma is the job's, or
// estimated from the residuals less the rows' mean variance.
#pragma once

#include <map>
#include <set>
#include <string>
#include <utility>

#include <Eigen/Core>

#include "cellmetry/formats/recording.h"

namespace cellmetry {

// Measurement noise, per camera, along the camera's x, y and z (depth) axes.
struct NoiseSpec {
  std::map<std::string, Eigen::Vector3d> position_sigma_mm;   // camera -> sigma (given by job)
  std::map<std::string, Eigen::Vector3d> rotation_sigma_rad;  // camera -> sigma (given by job)
  double floor_mm = 1e-3;  // no sigma is taken smaller than this (exact simulated targets)
  double floor_rad = 1e-6;
  std::set<std::string> per_row_cameras;  // each row adds its own position covariance (above)
};

struct TargetNoise {
  Eigen::Vector3d position_mm = Eigen::Vector3d::Ones();
  Eigen::Vector3d rotation_rad = Eigen::Vector3d::Constant(1e-3);
  // Where sigma came from, in words: "job", "spread of 3 repeated captures at each of 250
  // poses", "spread of 2500 captures of a world-fixed target", "detections (N)", "residuals of a
  // first fit", "unknown".
  std::string source = "unknown";
  int repeat_groups = 0;  // groups with >= 2 captures that the estimate pooled
  // Each row adds its own position covariance to position_mm^2 (NoiseSpec::per_row_cameras);
  // the mean of the rows' variances per axis (mm^2), which a sigma from residuals leaves out.
  bool per_row = false;
  Eigen::Vector3d mean_row_variance_mm2 = Eigen::Vector3d::Zero();
};

// The position sigma of one observation's row: `noise`'s, with the observation's own covariance
// added where `noise.per_row` and the observation carries one.
Eigen::Vector3d RowPositionSigma(const TargetNoise& noise, const Observation& observation);

using NoiseKey = std::pair<std::string, std::string>;  // (camera, target)

struct NoiseModel {
  std::map<NoiseKey, TargetNoise> entries;
  const TargetNoise& at(const std::string& camera, const std::string& target) const;
  // Whether some camera and target's sigma is neither given nor measured: a first fit's
  // residuals are to give it.
  bool has_unknown() const;
};

// Repeatability of each (camera, target): pooled sigma over groups of repeated captures.
// Entries with no repeated captures are absent.
NoiseModel EstimateRepeatability(const Recording& recording);

// The detection covariances' sigma per (camera, target) whose every observation carries both.
NoiseModel DetectionAccuracy(const Recording& recording);

// The sigma used for fitting: job values, else detections or repeatability (floored), else
// "unknown" (1 mm, 1e-3 rad, to be re-estimated from residuals).
NoiseModel BuildNoiseModel(const Recording& recording, const NoiseSpec& spec);
// The same from `repeats`, EstimateRepeatability(recording) made already (an identification
// reports it too: once, not twice; on exp_a each was 1 % of the identification).
NoiseModel BuildNoiseModel(const Recording& recording, const NoiseSpec& spec,
                           const NoiseModel& repeats);

}  // namespace cellmetry
