// WorkcellResult: everything a workcell identification found (the "Result struct out").
//
// Written by result_io.h as YAML (frames and model parameters, ready to paste into a robot
// config), JSON (everything here) and CSV (one row per residual).
#pragma once

#include <cmath>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/stage_clock.h"
#include "cellmetry/cell/camera_left_out.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/estimation/estimation_quality.h"
#include "cellmetry/estimation/noise_model.h"
#include "cellmetry/estimation/solver.h"

namespace cellmetry {

// A frame with its uncertainty: sigma of the translation (mm) and of small rotations about the
// parent frame's axes (rad). Entries that were held have sigma 0 and `held` set.
struct FrameEstimate {
  std::string name;    // "ur3.base", "tool", "cam1"
  std::string parent;  // "world" or "<robot>.flange"
  Pose pose;
  Eigen::Vector3d sigma_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma_rad = Eigen::Vector3d::Zero();
  // Their parts (Uncertainty): statistical, systematic and from uncertain inputs, x y z then
  // rx ry rz.
  Eigen::Matrix<double, 6, 1> sigma_statistical = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> sigma_systematic = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> sigma_inputs = Eigen::Matrix<double, 6, 1>::Zero();
  std::array<bool, 6> held{};
  // Moves with a parameter held because the data cannot determine it (no gauge prior could be
  // had): its value is the hold's, not the data's, and sigma does not cover that.
  std::array<bool, 6> undetermined{};
};

struct ScalarEstimate {
  std::string name;  // "ur3.model.j2.d"
  std::string unit;
  double nominal = 0.0;
  double value = 0.0;
  double sigma = 0.0;
  double sigma_statistical = 0.0;  // its parts (Uncertainty)
  double sigma_systematic = 0.0;
  double sigma_inputs = 0.0;
  bool held = false;
  bool undetermined = false;  // as FrameEstimate::undetermined
  std::string convention;     // held by convention: what it puts where (Parameter::convention)
};

// RMS of residuals along the camera's x, y and depth axes, and of their 3D length.
// Add() errors one by one (running sums of squares), then Finish() once to turn them into RMS.
struct ResidualRms {
  int count = 0;
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  double norm = 0.0;

  void Add(const Eigen::Vector3d& error) {
    axis += error.cwiseAbs2();
    ++count;
  }
  void Finish() {
    if (count == 0) return;
    const Eigen::Vector3d mean_square = axis / count;
    norm = std::sqrt(mean_square.sum());
    axis = mean_square.cwiseSqrt();
  }
};

inline ResidualRms RmsOf(const std::vector<Eigen::Vector3d>& errors) {
  ResidualRms rms;
  for (const auto& e : errors) rms.Add(e);
  rms.Finish();
  return rms;
}

// An observation the outlier test left out (outliers.h).
struct Outlier {
  int line = 0;  // in observations.csv (0: an observation built in memory)
  int sample = 0;
  std::string camera, target, kind;  // kind: "position" | "rotation"
  double score = 0.0;                // q / s^2: how many times the robust scale it lies out
  double threshold = 0.0;            // the test's chi-square quantile it exceeded
};

// What a residual row measures: a position (mm) or a rotation (rad), as the Problem's blocks say.
using ResidualKind = ResidualInfo::Kind;

struct ResidualRow {
  int observation = 0;
  int sample = 0;
  int pose = 0;
  std::string camera;
  std::string target;
  ResidualKind kind = ResidualKind::kPosition;  // kPosition (mm) or kRotation (rad)
  Eigen::Vector3d error;                        // prediction - measurement, camera axes
  Eigen::Vector3d normalized;                   // error / sigma
};

// "position", "rotation" or "prior": a kind as residuals.csv and the reports write it.
inline const char* ResidualKindName(ResidualKind kind) {
  switch (kind) {
    case ResidualKind::kPosition: return "position";
    case ResidualKind::kRotation: return "rotation";
    case ResidualKind::kPrior: return "prior";
  }
  return "position";
}

// One held-out position row: which observation of which pose, and its
// |prediction - measurement|^2 (mm^2).
struct HeldOutError {
  int observation = 0;
  int pose = 0;
  double squared_mm2 = 0.0;
};

struct HeldOut {
  int folds = 0;
  ResidualRms total;  // target positions, mm
  // total.norm's standard error, the held-out poses as independent draws (a pose's rows, its
  // cameras and repeated captures, share its error: statistics.h's grouped form). The folds
  // share most of their training poses, so even poses are not quite independent and no
  // unbiased estimate of a k-fold figure's variance exists (Bengio & Grandvalet, JMLR 5, 2004):
  // read it as a lower bound, good for telling a real difference from the poses' own scatter.
  double total_se_mm = 0.0;
  std::vector<HeldOutError> errors;  // total's rows, fold by fold, for paired comparisons
  std::map<std::string, ResidualRms> per_camera;
  std::vector<ResidualRms> per_fold;            // the same folds for the same poses and seed
  std::vector<double> per_fold_normalized_rms;  // the same folds in sigmas, over every carried-
                                                // target row (positions and used rotations)
};

// How much better one model's cross-validation is than another's (CompareHeldOut, workcell.h).
struct HeldOutGain {
  double gain_mm = 0.0;  // before.total.norm - after.total.norm
  double standard_error_mm = 0.0;
  bool paired = false;  // the same rows in both
};

// Fresh positions a result was scored on (prediction - measurement, camera axes).
struct RecordingScore {
  std::string recording;
  ResidualRms before;  // with the closed-form start (nominal model)
  ResidualRms after;   // with the answer
  double mean_after_mm = 0.0;
  double max_after_mm = 0.0;
  // Its poses with a joint beyond the ranges the result was fitted on
  // (RobotModelRecord::joint_ranges_rad, JointsOutsideRanges), and the 3D RMS with the answer
  // there and on the rest (mm; NaN over no pose). There the model is extrapolated.
  int poses = 0;
  int poses_beyond_calibration = 0;
  double rms_beyond_calibration_mm = NAN;
  double rms_within_calibration_mm = NAN;
};

// One scored point: prediction - measurement and its predicted covariance, camera axes.
struct HeldOutPoint {
  int sample = 0;
  int pose = 0;  // the sample's pose: captures of one pose share its error
  std::string camera;
  std::string target;
  Eigen::Vector3d error_mm = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance_mm2 = Eigen::Matrix3d::Zero();
  double normalized_squared = 0.0;  // e^T C^-1 e: chi-square with 3 dof when honest
  bool beyond_calibration = false;  // a joint of its pose beyond the calibration's (joint_ranges.h)
};

// A joint some scored pose reads beyond the range the calibration's poses span (joint_ranges.h).
struct JointBeyondCalibration {
  std::string robot;
  int joint = 0;  // 1-based
  double calibration_min_rad = 0.0, calibration_max_rad = 0.0;
  double scored_min_rad = 0.0, scored_max_rad = 0.0;  // over every scored pose
  int poses = 0;                                      // scored poses beyond it
};

// The held-out score split at the calibration's joint ranges (joint_ranges.h).
struct BeyondCalibration {
  std::vector<JointBeyondCalibration> joints;  // only joints some scored pose goes beyond
  int poses = 0;                               // scored poses with any joint beyond
  double rms_within_mm = NAN;                  // of the points within every range
  double rms_beyond_mm = NAN;                  // of the points beyond one or more
};

struct WorkcellResult;

// The same robot in another setup, its frames registered again (held_out_setup.h).
struct HeldOutSetupScore {
  std::string recording;
  std::vector<int> registration_poses;  // pose ids, in capture order
  int scored_poses = 0;
  double rms_mm = 0.0;     // of |error| over the scored points
  double rms_se_mm = 0.0;  // its standard error, the points as independent draws (statistics.h)
  double mean_mm = 0.0;
  double max_mm = 0.0;
  double registration_rms_mm = 0.0;  // the registration fit's own points
  double nominal_rms_mm = 0.0;       // the nominal model registered on the same poses
  double within_95 = 0.0;            // share of points inside their 95 % ellipsoid
  double mean_normalized = 0.0;      // mean of e^T C^-1 e / 3 (1 when the sigma are right)
  double median_sigma_mm = 0.0;      // median of sqrt(trace C_p): a point's 3D sigma
  std::vector<HeldOutPoint> points;
  BeyondCalibration beyond_calibration;
  // The calibrated geometry and effects, held, with the new setup's frames registered: the
  // result a user compensates with in that setup (`cellmetry compensate`). Its uncertainty is S
  // (held_out_setup.h), the joint covariance of the calibrated entries and the registered
  // frames, so that a compensated command's sigma holds both.
  std::shared_ptr<const WorkcellResult> registered;
};

// What a result records of each robot's model so that it can be rebuilt without the job
// (`cellmetry export`, core/exports): the robot config it was built from, as text (the file may
// change or go later), and every model parameter's value at the answer, fitted or held.
struct RobotModelRecord {
  std::string robot;                  // as in the recording
  std::string config_file;            // where the config was read, for messages
  std::string config_text;            // "" when the job was built in memory
  std::vector<Parameter> parameters;  // every parameter: `nominal` = its value at the answer,
                                      // `fixed` = held in this job
  // Each joint's [min, max] reading (rad) over the calibration's samples: where the model was
  // measured (joint_ranges.h). Empty when the recording has no samples of the robot.
  std::vector<std::pair<double, double>> joint_ranges_rad;
};

// What a result records of each effect in its prediction chain so that it can be rebuilt
// without the job (`cellmetry compensate`): the block that built it; its fitted values are
// model_parameters' "<name>.<parameter>" entries.
struct EffectRecord {
  std::string name;    // "ur3.compliance_j3"
  std::string robot;   // the robot whose chain it is in
  std::string type;    // the effect plugin's type
  std::string stage;   // "joint", "flange" or "measurement"
  std::string config;  // WorkcellEffect::config ("" when built in memory)
};

// A robot's base in another robot's base (robot_pairs.h), sigma from both bases' joint
// covariance, their cross-covariance included.
struct RobotPairEstimate {
  FrameEstimate frame;  // name "<b>.base", parent "<a>.base"; sigma about a's axes
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();  // x y z mm,
                                                                                 // rx ry rz rad
};

struct WorkcellResult {
  CameraModel camera_model = CameraModel::kStaticCameras;
  ResidualForm residual_form = ResidualForm::kCartesian;
  SolverSummary solver;
  std::vector<FrameEstimate> frames;
  std::vector<RobotPairEstimate> robot_to_robot;  // every ordered pair (robot_pairs.h)
  std::vector<ScalarEstimate> model_parameters;   // free or held-for-identifiability entries
  std::vector<RobotModelRecord> robot_models;     // each robot's model, whole (exports)
  std::vector<EffectRecord> effect_models;        // each effect of the chain (compensate)
  Eigen::Vector3d gravity_base = Eigen::Vector3d(0, 0, -9.81);  // the job's, m/s^2 (effects)
  std::vector<UnidentifiableParameter> unidentifiable;
  std::vector<WeakParameter> weakly_identified;  // see WorkcellProblem::weak_vif
  Uncertainty uncertainty;
  std::vector<CorrelatedPair> strong_correlations;
  NoiseModel noise;                                 // sigma used for weighting
  NoiseModel repeatability;                         // the noise floor from repeated captures
  std::map<std::string, ResidualRms> position_rms;  // "camera/target" -> mm
  std::map<std::string, ResidualRms> rotation_rms;  // "camera/target" -> rad
  std::vector<ResidualRow> residuals;
  std::vector<Outlier> outliers;  // left out by the outlier test (outliers.h)
  HeldOut held_out;
  std::map<std::string, HeldOut> other_models;  // compare_camera_models: name -> held-out
  std::vector<CameraLeftOut> cameras_left_out;  // each camera left out in turn (two or more)
  std::vector<std::string> unused_cameras;      // the job's `use: false` cameras
  std::map<std::string, int> skipped;           // observation skip reasons
  std::vector<std::string> warnings;
  WorkcellEstimate start;                           // the closed-form start, or the warm one
  WorkcellEstimate estimate;                        // the answer
  std::optional<RecordingScore> validation;         // set by the caller (ScoreOnRecording)
  std::optional<HeldOutSetupScore> held_out_setup;  // set by the caller (ScoreHeldOutSetup)
  std::vector<StageTime> stages;                    // where the time went (stage_clock.h)
};

}  // namespace cellmetry
