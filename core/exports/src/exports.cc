// The export formats by name (exports.h).
#include "cellmetry/exports/exports.h"

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/text.h"
#include "cellmetry/exports/robot_config_export.h"
#include "cellmetry/exports/tf_export.h"
#include "cellmetry/exports/ur_kinematics_export.h"
#include "cellmetry/exports/urdf_export.h"

namespace cellmetry {

const std::vector<std::string>& ExportFormatNames() {
  static const std::vector<std::string> names = {"urdf", "ur", "tf", "robot"};
  return names;
}

ExportFormat ParseExportFormat(const std::string& name, const std::string& where) {
  const auto& names = ExportFormatNames();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<ExportFormat>(i);
  }
  throw InputError({where, 0, 0}, "unknown export format '" + name + "'",
                   "Give one of: " + Join(names));
}

std::string ExportText(const CalibratedCell& cell, ExportFormat format, const std::string& robot,
                       const Registry& registry, ExportNaming naming) {
  if (naming == ExportNaming::kUr && format != ExportFormat::kUrdf && format != ExportFormat::kTf) {
    throw InputError({"--names", 0, 0}, "--names ur applies to --format urdf and tf",
                     "Leave out --names (the ur format has ur_description's names already)");
  }
  const bool ur = naming == ExportNaming::kUr;
  switch (format) {
    case ExportFormat::kUrdf: return UrdfExport(cell, ChooseRobot(cell, robot), naming);
    case ExportFormat::kUr: return UrKinematicsExport(cell, ChooseRobot(cell, robot));
    case ExportFormat::kTf: return TfLaunchExport(cell, ur ? ChooseRobot(cell, robot).name : "");
    case ExportFormat::kRobot: return RobotConfigExport(cell, ChooseRobot(cell, robot), registry);
  }
  return "";
}

}  // namespace cellmetry
