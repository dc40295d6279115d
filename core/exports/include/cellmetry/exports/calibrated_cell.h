// CalibratedCell: what `cellmetry export` and `cellmetry compensate` read from a result folder
// (result.json, read by ReadWorkcellResult, formats/workcell_result_file.h): every identified
// frame with its sigma, and each robot's model rebuilt through the registry at the fitted
// values.
//
// A robot's model comes from the robot config the result recorded (`robots.<name>.model_config`,
// the file's text at the time of the run) and every parameter's value at the answer
// (`model_values`), so an export never depends on the config file still being there or
// unchanged. A file the config names in turn (a `urdf` robot's URDF) is read again from where
// the config named it, relative to the config's folder as in the run: it must still be there.
// Lengths mm, angles rad; frames T_parent_child as everywhere in cellmetry.
//
// Reading throws InputError (exit code 2) naming result.json for: a missing folder or file, a
// file that is not a cellmetry result, a result written before results recorded their robots'
// models, and a recorded model the installed plugin no longer builds with those parameters.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/workcell_result_file.h"
#include "cellmetry/model/effect.h"
#include "cellmetry/model/robot_model.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

// CalibratedFrame (a frame with its sigma) and FittedScalar (a model or effect parameter with
// its sigma) are result.json's own (workcell_result_file.h).

struct CalibratedRobot {
  std::string name;                                // as in the recording
  std::string model_type;                          // the config's `type:` (a robot-model plugin)
  std::string model_file;                          // where the config was read at the run
  std::shared_ptr<const ConfigNode> model_config;  // the recorded config
  std::shared_ptr<const RobotModel> model;         // built from it by the registry
  std::vector<double> values;         // every model parameter at the answer, model order
  std::vector<FittedScalar> fitted;   // its parameters the job freed, with sigma
  std::vector<FittedScalar> effects;  // effect parameters fitted in its chain
  // Each joint's [min, max] (rad) over the calibration's samples: where the model was measured.
  // Empty for a result written before results recorded them.
  std::vector<std::pair<double, double>> joint_ranges_rad;
};

// An effect of the result's prediction chain (result.json `effects`), rebuilt through the
// registry from the block that built it, with its fitted values (`model_parameters`
// "<name>.<parameter>"). `effect` is null when the result does not record the block (the job was
// built in memory): what needs it (compensation) refuses the result then.
struct CalibratedEffect {
  std::string name;   // "ur3.compliance_j3"
  std::string robot;  // the robot whose chain it is in
  std::string type;   // the plugin's type
  std::string stage;  // "joint", "flange", "measurement"
  std::shared_ptr<const Effect> effect;
  std::vector<FittedScalar> parameters;  // the effect's parameters() order
};

// The covariance of the result's free parameters (result.json `free_parameters`, `sigma`,
// `correlation`), by name: what relative frames' sigma is propagated from.
struct ParameterCovariance {
  std::vector<std::string> names;
  Eigen::MatrixXd covariance;
  // Index of `name`, or -1 when it was not free.
  int Find(const std::string& name) const;
};

struct CalibratedCell {
  std::string folder;     // the result folder as given
  std::string json_path;  // <folder>/result.json, for messages
  std::vector<CalibratedFrame> frames;
  std::vector<CalibratedRobot> robots;
  std::vector<FittedScalar> camera_effects;  // measurement effects ("camera.<type>.<param>")
  std::vector<CalibratedEffect> effects;     // every effect of the chain; empty in results
                                             // written before results recorded them
  Eigen::Vector3d gravity_base = Eigen::Vector3d(0, 0, -9.81);  // m/s^2, the job's
  ParameterCovariance covariance;
};

CalibratedCell ReadCalibratedCell(const std::string& result_folder, const Registry& registry);

// The frame called `name`, or nullptr.
const CalibratedFrame* FindFrame(const CalibratedCell& cell, const std::string& name);

// The robot an export is about: `requested` by name, or the result's only robot when empty.
// InputError when the result has no robot, several and none requested, or none of that name.
const CalibratedRobot& ChooseRobot(const CalibratedCell& cell, const std::string& requested);

}  // namespace cellmetry
