// WorkcellProblem: what a workcell identification is asked to find (the "Problem struct in").
//
// Unknowns: each robot's base frame in the world (T_world_base), the pose of each target a robot
// carries on its flange (T_flange_target, "tool offset"), each static camera's pose in the world
// (T_world_cam) and any entry of a robot model the job frees. The `world` target defines the
// world frame; a cell without one (world_target empty: a delta arm seen by one stereo camera)
// takes the world to be its one robot's base, held where the job puts it (default: identity).
//
// A delta calibration is such a cell: one robot with its model free, one camera, one marker.
//
// Two observation models (DESIGN.md, issue "Foundation"):
//  - kStaticCameras (default): camera poses are parameters estimated from all captures jointly;
//    the world target's observations are measurements of them like any other.
//  - kPerFrame: as in the 2020 paper, each capture's own world-target pose is taken as exact and
//    no camera pose is estimated.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/estimation/noise_model.h"
#include "cellmetry/model/effect.h"
#include "cellmetry/model/frame_block.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

enum class CameraModel { kStaticCameras, kPerFrame };
std::string CameraModelName(CameraModel model);

// How a carried target's measured position is compared with the model (Poree 2023, sec. 6.1);
// the same maximum-likelihood problem either way:
//  - kCartesian: prediction - measurement in the camera frame, divided by sigma;
//  - kJointSpace: W (IK(measured point in the base, less the tool offset) - commanded joints),
//    where W whitens the joint error by the measurement covariance propagated through the IK
//    Jacobian at the start (W^T W = (J Sigma J^T)^-1), so both weigh the data alike. Needs a
//    robot model with position inverse kinematics (a flange that only translates).
enum class ResidualForm { kCartesian, kJointSpace };

// How gross outliers are found (outliers.h; the job's `outliers:`). kRobust: a robust first
// fit's rows are tested, then the plain fit's; kPlain: the plain fit's rows only (what 10 % of
// gross errors hide from); kOff: every observation is kept.
enum class OutlierTest { kRobust, kPlain, kOff };
std::string ResidualFormName(ResidualForm form);

// A frame on a robot's flange: a target it carries (T_flange_target), or a camera riding on it
// (eye in hand: `camera` set, the frame is T_flange_camera, named "<robot>.<camera>", and what
// that camera measures is the world target; hand_eye_start.h finds its start).
struct WorkcellTool {
  std::string target;          // recording target carried by the robot, or "<robot>.<camera>"
  FrameBlockSpec flange_tool;  // start = nominal T_flange_target
  std::string camera;          // not empty: the camera riding on the flange (eye in hand)
  bool start_given = false;    // the job gave the frame's start (else: closed form)
  bool is_camera() const { return !camera.empty(); }
};

struct WorkcellRobot {
  std::string name;  // as in the recording
  std::shared_ptr<const RobotModel> model;
  std::string model_file;                   // where the model came from, for the report
  std::string model_config;                 // that file's text, for the result (exports
                                            // rebuild the model from it)
  std::vector<Parameter> model_parameters;  // nominal values and fixed flags for this job
  FrameBlockSpec base;                      // `free` flags; start is found in closed form
  std::optional<Pose> base_start;           // a user-given start (skips the closed form)
  // A robot standing level (`base: {level: {sigma_rad}}`): a prior that its base's z axis is
  // the world's, within this standard uncertainty per axis (rad), on its rotation about the
  // world's x and y. None: the base's tilt is what the data and the free flags make it.
  std::optional<double> level_sigma_rad;
  std::vector<WorkcellTool> tools;
};

// An effect (effect.h) in the prediction chain: joint and flange effects act on one robot's
// chain, measurement effects on every observation of their cameras. Its parameters start at
// zero (no effect) unless the start estimate has values for it.
struct WorkcellEffect {
  std::string name;   // block name, "<robot>.<effect>[_<what>]", e.g. "ur3.backlash_j2"
  std::string robot;  // the robot whose chain it is in
  std::shared_ptr<const Effect> effect;
  // The effect block that built it, one line of YAML ("{type: backlash, joints: [2]}"), so that
  // a result can rebuild it (`cellmetry compensate`); "" when it was built in memory.
  std::string config;
  // Not empty: held at these values (an effect calibrated on another recording, carried to
  // this one), one per parameter; empty: free, from zero or the start.
  std::vector<double> held_values;
};

// An input the job holds at a stated value that is itself uncertain (consider_covariance.h):
// an effect held at zero whose every parameter is uncertain by `sigma` (its unit), e.g. a
// board's printed size; or a robot's held model parameters, uncertain by `model_sigma` per unit
// ("mm", "rad"). They widen sigma (its `inputs` part); they never move the answer.
struct UncertainInputs {
  std::vector<std::pair<WorkcellEffect, double>> effects;
  std::map<std::string, std::map<std::string, double>> model_sigma;  // robot -> unit -> sigma
  bool empty() const { return effects.empty() && model_sigma.empty(); }
};

// A static camera's start and which of its pose entries are free (a job's `cameras:`); a camera
// the job does not name starts in closed form with every entry free. `use: false` leaves every
// observation of the camera out (what the cell says without it).
struct WorkcellCamera {
  std::optional<Pose> start;  // T_world_cam; none: closed form
  std::array<bool, 6> free = {true, true, true, true, true, true};
  bool use = true;
};

// Where everything is, at the start or at the answer of an identification.
struct WorkcellEstimate {
  std::map<std::string, Pose> T_world_base;            // robot -> base
  std::map<std::string, std::vector<double>> model;    // robot -> model parameter values
  std::map<std::string, Pose> T_flange_target;         // target -> tool offset; a camera riding
                                                       // on a flange: "<robot>.<camera>" ->
                                                       // T_flange_camera
  std::map<std::string, Pose> T_world_cam;             // camera -> pose (static cameras only)
  std::map<std::string, std::vector<double>> effects;  // effect -> parameter values (none: zero)
};

struct WorkcellProblem {
  std::vector<WorkcellRobot> robots;
  CameraModel camera_model = CameraModel::kStaticCameras;
  ResidualForm residual = ResidualForm::kCartesian;
  std::string world_target = "world";  // "": no world target (see above)
  std::map<std::string, WorkcellCamera> cameras;
  bool use_tool_rotation = false;  // also fit the carried targets' measured rotations
  NoiseSpec noise;
  // A direction of parameter space whose scaled singular value falls below this (relative to
  // the largest) is not identifiable; the parameter most involved is held at its nominal value.
  double identifiability_tolerance = 1e-8;
  // Variance inflation above which a parameter is reported as weakly identified. A delta arm
  // calibrated on a spread pose set shows at most ~1e4 (its parameters are coupled); all
  // positions at one height give ~2e5 for the rod lengths, homing offsets and camera z.
  double weak_vif = 1e5;
  int folds = 5;  // k-fold cross-validation by pose (0 = off)
  // With two or more static cameras seeing the robots' targets, identify the cell again
  // without each of them and compare (camera_left_out.h). A job's default is on
  // (`validation: {leave_one_camera_out}`); a problem built in memory's is off.
  bool leave_one_camera_out = false;
  unsigned seed = 1;                   // fold assignment
  bool compare_camera_models = false;  // also report the other observation model's held-out RMS
  OutlierTest outlier_test = OutlierTest::kRobust;
  std::vector<WorkcellEffect> effects;                          // none: the geometric model alone
  UncertainInputs uncertain_inputs;                             // none: sigma from the data alone
  Eigen::Vector3d gravity_base = Eigen::Vector3d(0, 0, -9.81);  // m/s^2 in every base frame
  // A neighbouring fit's answer to start from instead of the closed form (InitialEstimate): the
  // physics finder's refits start from the model they add one effect to (its parameters at
  // zero). Used only where it places every robot, tool and static camera the data has.
  std::optional<WorkcellEstimate> warm_start;
};

}  // namespace cellmetry
