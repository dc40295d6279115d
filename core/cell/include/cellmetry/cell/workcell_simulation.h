// Simulated workcell recordings with known truth, and scoring a result against that truth.
//
// SimulateWorkcell plays robots through joint poses in front of static cameras and writes what
// ideal pose-estimating cameras would report (world target and carried targets, in each camera's
// frame), plus Gaussian noise of the given sigma along the camera's x, y and depth axes and about
// them. Every camera sees every target (no images, no occlusion). The truth (every frame, every
// model parameter) travels in truth.yaml, which a calibration never reads.
//
// One simulator for every cell. A delta arm's kinematic calibration (the 2023 report's sec. 6
// setting) is a cell without a world target: its base is the world, its truth is drawn around
// the nominal arm (`errors:` of the robot and of the camera, simulation_draws.h), its commands
// come from a pose set (nominal inverse kinematics of points in the workspace), and its marker
// is a point: `measures: position` writes no rotation.
//
// Effects (effect.h) can be concealed in the recording: `effects:` under a robot (joint and
// flange effects) or at the top level (measurement effects), each
//   {effect: {type: backlash, joints: [2]}, values: {j2.backlash: 0.002}}
// with `timeline: {seconds_per_sample, temperature_start_c, temperature_end_c}` for drifts. The
// true values go to truth.yaml's model section as <robot>.<type>.<parameter>. `concealed:` lists
// physics that is not the library's (disturbance.h), read by the DisturbanceReader the caller
// gives; truth.yaml records its magnitude as concealed.<kind>.magnitude.
//
// With an `images:` section (image_simulation.h) the recording carries rendered images of every
// camera instead of observations (WorkcellViews says what each camera sees): `cellmetry detect`
// measures them, with occlusion, perspective and the detector's own errors.
//
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "cellmetry/cell/disturbance.h"
#include "cellmetry/cell/simulation_draws.h"
#include "cellmetry/cell/truth.h"
#include "cellmetry/cell/workcell_problem.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/imaging/image_simulation.h"
#include "cellmetry/model/effect.h"
#include "cellmetry/model/robot_model.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

// An effect concealed in a simulation: its plugin and the true values of its parameters.
struct SimulatedEffect {
  std::string name;  // "<robot>.<type>" (truth.yaml: <name>.<parameter>)
  std::shared_ptr<const Effect> effect;
  std::vector<double> values;
};

struct SimulatedRobot {
  std::string name;
  std::shared_ptr<const RobotModel> model;
  std::vector<double> nominal_values;   // the model's config values
  std::vector<double> given_values;     // nominal plus `model_errors:`
  std::vector<double> model_values;     // true: given plus the drawn errors
  ModelErrors errors;                   // drawn into model_values (none: zero)
  std::optional<PoseSetSpec> pose_set;  // commands drawn when simulated
  Pose T_world_base;
  std::map<std::string, Pose> T_flange_target;   // carried targets
  std::map<std::string, Pose> T_flange_camera;   // cameras riding on the flange (eye in
                                                 // hand): they see the world target
  std::set<std::string> point_targets;           // measured as positions only (a dot)
  std::vector<std::vector<double>> joint_poses;  // q per commanded pose
  std::vector<double> payloads_kg;               // cycled over the commanded poses
                                                 // (samples.csv payload); empty: none
  std::vector<SimulatedEffect> effects;          // joint and flange effects it has
};

// Clock and temperature of the captures (samples.csv t, temperature), for drifting effects.
struct SimulatedTimeline {
  double seconds_per_sample = 0.0;                               // 0: no times recorded
  std::optional<double> temperature_start_c, temperature_end_c;  // linear ramp over the run
};

// A camera as simulated: its nominal pose, the error drawn into the truth, its field of view.
struct SimulatedCamera {
  Pose T_world_cam_nominal;
  CameraErrors errors;
  // Half angles of the field of view about the camera's x and y axes (rad), for the camera_view
  // pose set; OAK-D-like default (1280 x 800 px, f = 880 px).
  Eigen::Vector2d half_fov_rad = Eigen::Vector2d(0.629, 0.427);
  // Records a carried target only while its origin lies inside that field of view, as a real
  // camera does (`in_view_only: true`). Off by default: an ideal camera that sees every board
  // wherever it is, which makes a lens's error at the edge of sight larger than any real lens
  // shows. The world target is always recorded (it must be in view of the nominal pose: the
  // reader checks).
  bool in_view_only = false;
};

struct WorkcellSimulationSpec {
  std::vector<SimulatedRobot> robots;
  std::map<std::string, Pose> T_world_cam;  // the truth
  std::map<std::string, SimulatedCamera> cameras;
  std::string world_target = "world";  // "": none (the one robot's base is the world)
  Eigen::Vector3d sigma_position_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma_rotation_rad = Eigen::Vector3d::Zero();
  int repeats = 1;    // captures per commanded pose
  unsigned seed = 1;  // draws the truth (errors), and the noise unless noise_seed is set
  // Draws the pose sets' commands and the noise: a second recording of the same truth (a
  // validation set) keeps `seed` and changes this (`poses: {seed}`).
  unsigned noise_seed = 1;
  std::vector<SimulatedEffect> measurement_effects;           // depth bias and the like
  std::vector<std::shared_ptr<const Disturbance>> concealed;  // physics outside the library
  SimulatedTimeline timeline;
  Eigen::Vector3d gravity_base = Eigen::Vector3d(0, 0, -9.81);
  std::optional<ConfigNode> images;  // render images instead of writing observations
};

Recording SimulateWorkcell(const WorkcellSimulationSpec& spec, WorkcellTruth* truth);
// The same with the caller's random stream (pose sets drawn first, then the noise).
Recording SimulateWorkcell(const WorkcellSimulationSpec& spec, WorkcellTruth* truth,
                           std::mt19937& rng);

// Draws the truth from `rng`: every robot's model errors around its given values, then every
// camera's pose errors around its nominal pose (simulation_draws.h). LoadWorkcellSimulation
// draws it from `seed`; a caller drawing again from the same seed gets the same truth.
void DrawTruth(WorkcellSimulationSpec* spec, std::mt19937& rng);

// A fresh draw of a simulation from one random stream: the truth, then its recording (pose
// sets, noise): the report's protocol for repeated simulated calibrations.
struct SimulatedDraw {
  WorkcellSimulationSpec truth;
  Recording recording;
};
SimulatedDraw DrawAndSimulate(const WorkcellSimulationSpec& spec, std::mt19937& rng);

// The truth as an estimate (every frame and model value), for predictions and comparisons.
WorkcellEstimate TruthEstimate(const WorkcellSimulationSpec& spec);

// The calibration problem a simulation without a world target poses (the delta report's):
// every model parameter free, the base held (it is the world), each tool held at the model's
// nominal tool, the cameras free from the closed form, the simulation's sigma (or
// `noise_free_sigma_mm` when it has none: it only scales the weights), no cross-validation.
WorkcellProblem SimulatedProblem(const WorkcellSimulationSpec& spec, ResidualForm residual,
                                 double noise_free_sigma_mm = 0.01);

// Where `robot`'s pose sets may put its target (simulation_draws.h), as seen by `camera` ("" with
// one camera: that one) at its nominal pose.
PoseSetGeometry PoseSetGeometryOf(const WorkcellSimulationSpec& spec, const SimulatedRobot& robot,
                                  const std::string& camera);

// Holds every model parameter whose name ends in `suffix` (".r": only R - r is identifiable).
void HoldModelParameters(const std::string& suffix, WorkcellProblem* problem);

// Where every target is in every camera's frame, per sample of `recording` (SimulateWorkcell's).
std::vector<SampleView> WorkcellViews(const WorkcellSimulationSpec& spec,
                                      const Recording& recording);

// The simulation's camera and target names, for its `images:` section.
std::vector<std::string> CameraNames(const WorkcellSimulationSpec& spec);
std::vector<std::string> TargetNames(const WorkcellSimulationSpec& spec);

// Reads a simulation spec file (docs/formats.md); robot models come from the registry,
// `concealed:` entries from `read_disturbance` (an InputError there without one).
WorkcellSimulationSpec LoadWorkcellSimulation(const std::string& path, Registry& registry,
                                              const DisturbanceReader& read_disturbance = {});

}  // namespace cellmetry
