// Simulated workcell recordings with known truth, and scoring a result against that truth.
//
// SimulateWorkcell plays robots through joint poses in front of static cameras and writes what
// ideal pose-estimating cameras would report (world target and carried targets, in each camera's
// frame), plus Gaussian noise of the given sigma along the camera's x, y and depth axes and about
// them. Every camera sees every target (no images, no occlusion). The truth (every frame, every
// model parameter) travels in truth.yaml, which a calibration never reads.
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
// truth.yaml:  format: cellmetry-truth/1
//              frames: {<name>: {parent, xyz, rvec}}      # same names as result.yaml
//              model:  {<robot>.model.<param>: value}
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cellmetry/cell/disturbance.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/model/effect.h"
#include "cellmetry/imaging/image_simulation.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/registry/registry.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

// An effect concealed in a simulation: its plugin and the true values of its parameters.
struct SimulatedEffect {
  std::string name;                     // "<robot>.<type>" (truth.yaml: <name>.<parameter>)
  std::shared_ptr<const Effect> effect;
  std::vector<double> values;
};

struct SimulatedRobot {
  std::string name;
  std::shared_ptr<const RobotModel> model;
  std::vector<double> model_values;                  // true model parameters
  Pose T_world_base;
  std::map<std::string, Pose> T_flange_target;       // carried targets
  std::vector<std::vector<double>> joint_poses;      // q per commanded pose
  std::vector<double> payloads_kg;                   // cycled over the commanded poses
                                                     // (samples.csv payload); empty: none
  std::vector<SimulatedEffect> effects;              // joint and flange effects it has
};

// Clock and temperature of the captures (samples.csv t, temperature), for drifting effects.
struct SimulatedTimeline {
  double seconds_per_sample = 0.0;     // 0: no times recorded
  std::optional<double> temperature_start_c, temperature_end_c;  // linear ramp over the run
};

struct WorkcellSimulationSpec {
  std::vector<SimulatedRobot> robots;
  std::map<std::string, Pose> T_world_cam;
  std::string world_target = "world";
  Eigen::Vector3d sigma_position_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma_rotation_rad = Eigen::Vector3d::Zero();
  int repeats = 1;          // captures per commanded pose
  unsigned seed = 1;
  std::vector<SimulatedEffect> measurement_effects;  // depth bias and the like
  std::vector<std::shared_ptr<const Disturbance>> concealed;  // physics outside the library
  SimulatedTimeline timeline;
  Eigen::Vector3d gravity_base = Eigen::Vector3d(0, 0, -9.81);
  std::optional<ConfigNode> images;  // render images instead of writing observations
};

struct FrameTruth {
  std::string parent;
  Pose pose;
};

struct WorkcellTruth {
  std::map<std::string, FrameTruth> frames;
  std::map<std::string, double> model;
};

Recording SimulateWorkcell(const WorkcellSimulationSpec& spec, WorkcellTruth* truth);

// Where every target is in every camera's frame, per sample of `recording` (SimulateWorkcell's).
std::vector<SampleView> WorkcellViews(const WorkcellSimulationSpec& spec,
                                      const Recording& recording);

// The simulation's camera and target names, for its `images:` section.
std::vector<std::string> CameraNames(const WorkcellSimulationSpec& spec);
std::vector<std::string> TargetNames(const WorkcellSimulationSpec& spec);

std::string TruthYaml(const WorkcellTruth& truth);
WorkcellTruth ReadTruth(const std::string& path);

// Reads a simulation spec file (docs/formats.md); robot models come from the registry,
// `concealed:` entries from `read_disturbance` (an InputError there without one).
WorkcellSimulationSpec LoadWorkcellSimulation(const std::string& path, Registry& registry,
                                              const DisturbanceReader& read_disturbance = {});

// Error of each estimate against the truth, in units and in its own sigma.
struct EvaluatedQuantity {
  std::string name;         // "ur3.base.x", "ur3.base.rot_x", "ur3.model.j2.d"
  std::string unit;
  double error = 0.0;       // estimate - truth (rotations: log(R_est R_true^T), parent axes)
  double sigma = 0.0;
  double normalized() const { return sigma > 0 ? error / sigma : (error == 0 ? 0.0 : INFINITY); }
};

struct WorkcellEvaluation {
  std::vector<EvaluatedQuantity> quantities;  // held entries (sigma 0) are skipped
  double max_translation_error_mm = 0.0;
  double max_rotation_error_rad = 0.0;
  double max_abs_normalized = 0.0;
};

// `result` is result.json (result_io.h); frames and model parameters absent from the truth are
// an InputError naming `truth_origin`.
WorkcellEvaluation EvaluateWorkcell(const nlohmann::json& result, const WorkcellTruth& truth,
                                    const std::string& truth_origin);

}  // namespace cellmetry
