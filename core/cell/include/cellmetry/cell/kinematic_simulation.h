// Simulated kinematic calibrations with known truth (the 2023 delta report's section 6 setup).
//
// A truth is drawn around the nominal arm: every length off by up to `dimensions_mm`, every
// homing offset by up to `homing_increments` motor increments, the camera by up to `camera_mm`
// and `camera_rad` per axis (uniform). Commands come from the nominal model's inverse kinematics
// of points drawn from a pose set, exactly as a controller that believes the nominal model would
// command them; the recording holds what the true arm then does, seen by the true camera, with
// Gaussian noise of sigma along the camera's x, y and depth axes.
//
// Pose sets (report, sec. 6.2), any size, inside the robot config's workspace cylinder:
//   camera_view        uniform over the part of the workspace inside the camera's field of view
//   uniform_workspace  uniform over the whole cylinder
//   boundaries         uniform over the cylinder's surface (side, top and bottom by area)
#pragma once

#include <memory>
#include <optional>
#include <utility>
#include <random>
#include <string>
#include <vector>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/imaging/image_simulation.h"
#include "cellmetry/cell/kinematic_calibration.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/registry/registry.h"
#include "cellmetry/cell/workcell_simulation.h"

namespace cellmetry {

enum class PoseSet { kCameraView, kUniformWorkspace, kBoundaries };
std::string PoseSetName(PoseSet set);
// Raises InputError at `node` for an unknown name.
PoseSet ParsePoseSet(const ConfigNode& node);

struct TruthErrors {
  double dimensions_mm = 1.0;
  double homing_increments = 5.0;
  double camera_mm = 1.0;
  double camera_rad = 0.01;
};

struct KinematicSimulationSpec {
  std::string robot = "delta";
  std::string target = "marker";
  std::string camera = "stereo";
  std::shared_ptr<const RobotModel> model;
  std::string model_file;
  Pose T_base_cam_nominal;
  // Half angles of the camera's field of view about its x and y axes (rad); OAK-D-like default
  // (1280 x 800 px, f = 880 px).
  Eigen::Vector2d half_fov_rad = Eigen::Vector2d(0.629, 0.427);
  TruthErrors errors;
  Eigen::Vector3d sigma_mm = Eigen::Vector3d::Zero();   // camera x, y, depth
  PoseSet pose_set = PoseSet::kUniformWorkspace;
  int count = 125;
  int repeats = 1;
  unsigned seed = 1;        // draws the truth
  unsigned pose_seed = 2;   // draws the commands and the noise: a second recording of the same
                            // truth (a validation set) keeps `seed` and changes this
  std::optional<ConfigNode> images;  // render images instead of writing observations
};

// Where the marker is in the camera frame for each sample of `recording` (the marker's face
// looks up the base z axis, toward a camera above the arm).
std::vector<SampleView> MarkerViews(const KinematicSimulationSpec& spec, const KinematicState& truth,
                                    const Recording& recording);

KinematicSimulationSpec LoadKinematicSimulation(const std::string& path, Registry& registry);

// The calibration problem a simulation poses: every model parameter free, camera free (closed-
// form start), marker held at the model's, sigma from the spec (or `noise_free_sigma_mm` when the
// simulation has no noise; it only scales the weights).
KinematicProblem SimulatedProblem(const KinematicSimulationSpec& spec, Formulation formulation,
                                  double noise_free_sigma_mm = 0.01);

// Holds every parameter whose name ends in `suffix` (e.g. ".r": only R - r is identifiable).
void HoldParametersNamed(const std::string& suffix, KinematicProblem* problem);

// The nominal state: model nominal values, marker from the model, the nominal camera.
KinematicState NominalState(const KinematicSimulationSpec& spec);
KinematicState DrawTruth(const KinematicSimulationSpec& spec, std::mt19937& rng);

// `count` commands of a pose set (nominal inverse kinematics of the drawn points).
std::vector<std::vector<double>> MakePoseSet(const KinematicSimulationSpec& spec, PoseSet set,
                                             int count, std::mt19937& rng);

// The recording of `commands` played on `truth` (noise from spec.sigma_mm, spec.repeats each).
Recording SimulateKinematic(const KinematicSimulationSpec& spec, const KinematicState& truth,
                            const std::vector<std::vector<double>>& commands, std::mt19937& rng);

WorkcellTruth KinematicTruthRecord(const KinematicSimulationSpec& spec,
                                   const KinematicState& truth);

// Distance between two states' predictions of the marker in the camera frame, over commands.
struct PredictionError {
  double mean_mm = 0.0;
  double max_mm = 0.0;
  double rms_mm = 0.0;
  int points = 0;
};
PredictionError ComparePredictions(const RobotModel& model, const KinematicState& estimate,
                                   const KinematicState& truth,
                                   const std::vector<std::vector<double>>& commands);

}  // namespace cellmetry
