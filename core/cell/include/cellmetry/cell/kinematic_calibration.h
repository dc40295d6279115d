// Kinematic calibration from measured marker positions (kinematic_problem.h).
//
//   CollectPointSamples   the recording's (command, measured position) pairs for the problem
//   EstimateCameraPose    T_base_cam in closed form: Kabsch/Umeyama between the measured points
//                         and the nominal model's prediction (the report's "SVD" step)
//   CalibrateKinematics   the full fit: closed-form start, identifiability, solve, covariance
//   PredictInCamera       where the calibrated (or any) model puts the marker, in camera axes
#pragma once

#include <map>
#include <string>
#include <vector>

#include "cellmetry/estimation/estimation_quality.h"
#include "cellmetry/cell/kinematic_problem.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/estimation/solver.h"
#include "cellmetry/cell/workcell_result.h"

namespace cellmetry {

// Raises InputError (naming the recording) if the robot, target or camera is missing, a sample
// has the wrong number of joints, or no observation is usable.
std::vector<PointSample> CollectPointSamples(const KinematicProblem& problem,
                                             const Recording& recording);

struct CameraPoseFit {
  Pose T_base_cam;
  double rms_mm = 0.0;          // of |T_base_cam * p_cam - p_model| over the samples
  int points = 0;
};

// Needs three samples not on one line; raises InputError otherwise. Samples whose nominal
// forward kinematics fails are skipped.
CameraPoseFit EstimateCameraPose(const KinematicProblem& problem,
                                 const std::vector<PointSample>& samples);

// The whole state of a kinematic model: enough to predict.
struct KinematicState {
  Pose T_base_cam;
  Eigen::Vector3d marker_mm = Eigen::Vector3d::Zero();
  std::vector<double> model_values;
};

// Joint values that put the marker at `p_cam_mm` (model inverse kinematics through the camera
// pose and marker offset) and their derivative d q / d p_cam; false where out of reach.
bool InverseInCamera(const RobotModel& model, const KinematicState& state,
                     const Eigen::Vector3d& p_cam_mm, Eigen::Vector3d* q,
                     Eigen::Matrix3d* d_q_d_p_cam);

// Marker position in the camera frame for command q; false where the model has no pose.
bool PredictInCamera(const RobotModel& model, const KinematicState& state,
                     const std::vector<double>& q, Eigen::Vector3d* p_cam_mm);

// Prediction - measurement (camera axes, mm) for every sample the model has a pose for.
std::vector<Eigen::Vector3d> PredictionErrors(const RobotModel& model, const KinematicState& state,
                                              const std::vector<PointSample>& samples);

struct KinematicResult {
  Formulation formulation = Formulation::kForward;
  SolverSummary solver;
  KinematicState state;                         // the answer
  CameraPoseFit closed_form_camera;             // the closed-form step, reported on its own
  FrameEstimate camera;                         // "camera" in "base", with sigma
  Eigen::Vector3d marker_sigma_mm = Eigen::Vector3d::Zero();
  std::vector<ScalarEstimate> model_parameters; // every model parameter (held ones: sigma 0)
  std::vector<UnidentifiableParameter> unidentifiable;
  std::vector<WeakParameter> weakly_identified;  // see KinematicProblem::weak_vif
  Uncertainty uncertainty;
  std::vector<CorrelatedPair> strong_correlations;
  Eigen::Vector3d sigma_mm = Eigen::Vector3d::Zero();  // measurement sigma used for weighting
  std::string sigma_source;                     // "job" or "residuals of a first fit"
  ResidualRms position_rms;                     // forward residuals at the answer, camera axes
  int samples = 0;
  std::vector<std::string> warnings;
};

KinematicResult CalibrateKinematics(const KinematicProblem& problem,
                                    const std::vector<PointSample>& samples,
                                    const SolverMaker& make_solver);

// The best any unbiased estimator can do on this design (Cramer-Rao): the RMS, over the
// `validation` commands, of the prediction error in the camera frame,
//   floor^2 = mean_v trace(G_v F^-1 G_v^T),   F = J^T J   (J whitened by sigma_mm),
// with J the calibration design's Jacobian and G_v the prediction's Jacobian, both at `truth`
// and over the free parameters that remain once `held` are held. docs/delta.md derives it.
double PredictionErrorFloorMm(const KinematicProblem& problem,
                              const std::vector<PointSample>& design,
                              const std::vector<std::vector<double>>& validation,
                              const KinematicState& truth, const Eigen::Vector3d& sigma_mm,
                              const std::vector<UnidentifiableParameter>& held);

}  // namespace cellmetry
