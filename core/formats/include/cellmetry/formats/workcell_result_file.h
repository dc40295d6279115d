// WorkcellResultFile: result.json (cellmetry-result/1) read back, typed: what the commands that
// start from a result (`evaluate`, `export`, `compensate`) take from it. The file is written by
// WriteWorkcellResult (cell/result_io.h; docs/formats.md lists every key); this is the one
// reader of it, low enough that every layer above (cell, exports, compensation) reads it the
// same way. Lengths mm, angles rad; frames T_parent_child as everywhere in cellmetry.
//
// Contract:
//  - ReadWorkcellResult(json_path) throws InputError naming the file for: a file it cannot open
//    ("cannot open the result"), one that is not JSON ("not a result file"), one whose `format`
//    is not cellmetry-result/1 ("not a cellmetry result"), and a key that is missing or holds
//    the wrong type ("malformed result: <key path>: ..."), the key path written out
//    ("frames.ur3.base.xyz_mm[2]").
//  - Required: frames, model_parameters, free_parameters, sigma, correlation. The rest may be
//    absent (a result without robots, robot pairs, effects or unidentifiable parameters, or
//    written before results recorded them): an empty list, or `records_robots` false and no
//    gravity.
//  - Nothing is checked beyond types: whether a robot's model can still be rebuilt from its
//    recorded config is the exports' question (calibrated_cell.h).
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

// A frame of the result (`frames.<name>`): T_parent_name with the sigma of its translation (mm)
// and of small rotations about the parent's axes (rad); a held entry has no sigma.
struct CalibratedFrame {
  std::string name;    // "ur3.base", "tool", "cam1"
  std::string parent;  // "world" or "<robot>.flange"
  Pose T_parent_frame;
  std::array<std::optional<double>, 6> sigma;  // x y z (mm), rx ry rz (rad); empty = held
};

// A scalar the fit reports beside the frames (`model_parameters[]`): a model parameter
// ("ur3.model.j2.d") or an effect's ("ur3.joint_compliance.k2", "camera.depth_bias.scale").
struct FittedScalar {
  std::string name;
  std::string unit;
  double value = 0.0;
  std::optional<double> sigma;  // empty: held (not identifiable), or not a number
  bool held = false;
};

// A robot's model as the run recorded it (`robots.<name>`): the config file's text and every
// model parameter's value at the answer, in the model's order.
struct ResultRobotModel {
  std::string robot;
  std::string model_file;    // where the config was read at the run
  std::string model_config;  // its text; empty when the job was built in memory
  std::vector<std::pair<std::string, double>> model_values;  // (parameter name, value)
  // Each joint's [min, max] (rad) over the calibration's samples; empty in results written
  // before they were recorded.
  std::vector<std::pair<double, double>> joint_ranges_rad;
};

// One robot's base in another's (`robot_to_robot.<key>`): T_parent_frame with its sigma
// propagated from both bases.
struct ResultRobotPair {
  std::string key;  // "T_ur3_ur5e"
  CalibratedFrame frame;
};

// An effect of the prediction chain (`effects.<name>`) and the block that built it.
struct ResultEffect {
  std::string name;    // "ur3.compliance_j3"
  std::string robot;   // the robot whose chain it is in
  std::string type;    // the plugin's type
  std::string stage;   // "joint", "flange", "measurement"
  std::string config;  // the block as one line of YAML; empty when the job was built in memory
};

// A parameter the data could not determine (`unidentifiable[]`) and the free ones its error
// moved into: what the data determined is partner - ratio * held.
struct ResultUnidentifiable {
  struct Partner {
    std::string name;
    double ratio = 0.0;
  };
  std::string name;
  std::vector<Partner> moves_with;
};

struct WorkcellResultFile {
  std::string path;                             // the file read, for messages
  std::vector<CalibratedFrame> frames;          // by name
  std::vector<FittedScalar> model_parameters;   // in the file's order
  bool records_robots = false;                  // false: written before results recorded them
  std::vector<ResultRobotModel> robots;         // by name
  std::vector<ResultRobotPair> robot_to_robot;  // by key
  std::vector<ResultEffect> effects;            // by name
  std::vector<ResultUnidentifiable> unidentifiable;
  std::optional<Eigen::Vector3d> gravity_base_m_s2;  // the job's gravity in the base, m/s^2
  // The free parameters' covariance as sigma and correlation, in `free_parameters` order.
  std::vector<std::string> free_parameters;
  std::vector<double> sigma;
  std::vector<std::vector<double>> correlation;
};

WorkcellResultFile ReadWorkcellResult(const std::string& json_path);

// The same for result.json's text; `origin` names it in messages.
WorkcellResultFile ParseWorkcellResult(const std::string& text, const std::string& origin);

}  // namespace cellmetry
