// `cellmetry export RESULT --format urdf|ur|tf|robot [--names model|ur]`: what a robot cell can
// load, from a result.
//
//   urdf    one serial arm: base in the world, calibrated joint origins, flange, tools
//           (urdf_export.h)
//   ur      one six-joint arm: Universal Robots' kinematics YAML for ur_description
//           (ur_kinematics_export.h)
//   tf      every frame as ROS 2 static transforms, sigma in comments (tf_export.h)
//   robot   one robot as a cellmetry robot config at its fitted values (robot_config_export.h)
//
// Layer: above the registry (robot models are built by name from the result's record), below
// cell; it reads result.json, never the pipeline's types. What is specific to a kind of robot
// lives in its plugin (RobotModel::AsSerialChain, CalibratedConfig); what is specific to a file
// format lives here; neither names the other. Files are written by export_file.h.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/exports/robot_links.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

enum class ExportFormat { kUrdf, kUr, kTf, kRobot };

// "urdf", "ur", "tf", "robot".
const std::vector<std::string>& ExportFormatNames();
// InputError located at `where` (e.g. "--format") for any other name, listing the known ones.
ExportFormat ParseExportFormat(const std::string& name, const std::string& where);

// The export's text. `robot`: the robot of urdf, ur and robot ("" = the result's only one);
// tf exports every frame and takes none, except with `naming` ur: the robot named so.
// `naming` (robot_links.h) applies to urdf and tf; InputError located at "--names" when it is
// ur for ur or robot.
std::string ExportText(const CalibratedCell& cell, ExportFormat format, const std::string& robot,
                       const Registry& registry, ExportNaming naming = ExportNaming::kModel);

}  // namespace cellmetry
