// `cellmetry export RESULT_DIR --format urdf|ur|tf|robot [--robot NAME] [--names model|ur]
// [-o FILE]`: a result as
// a file a robot cell loads (exports.h). Without -o the text goes to standard output. A file is
// written only where nothing is, or over an earlier export (kept as FILE.previous); a user's file
// only with --overwrite (export_file.h).
#include <cstdio>

#include "cellmetry/basics/error.h"
#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/exports/export_file.h"
#include "cellmetry/exports/exports.h"
#include "commands.h"

namespace cellmetry::app {

void AddExportCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand(
      "export",
      "write a result as a file a robot cell loads: urdf, ur (Universal Robots' "
      "kinematics YAML), tf (ROS 2 static transforms), robot (a cellmetry robot config)");
  static std::string result_folder, format_name, robot, output, naming_name = "model";
  static bool overwrite = false;
  cmd->add_option("result", result_folder, "result folder written by `cellmetry run`")->required();
  cmd->add_option("-f,--format", format_name, "urdf | ur | tf | robot")->required();
  cmd->add_option("--robot", robot, "the robot to export (urdf, ur, robot; default: the only one)");
  cmd->add_option("--names", naming_name,
                  "link and joint names of urdf and tf: model (the robot model's own, e.g. a "
                  "urdf robot's, else <robot>_joint<i>) or ur (ur_description's for a six-joint "
                  "arm: shoulder_pan_joint ... wrist_3_joint, base_link, tool0; tf: the --robot "
                  "or only robot)")
      ->capture_default_str();
  cmd->add_option("-o,--output", output, "file to write (default: standard output)");
  cmd->add_flag("--overwrite", overwrite,
                "replace a file cellmetry did not write (it is kept as FILE.previous)");
  cmd->callback([&context] {
    const ExportFormat format = ParseExportFormat(format_name, "--format");
    const ExportNaming naming = ParseExportNaming(naming_name, "--names");
    if (format == ExportFormat::kTf && !robot.empty() && naming != ExportNaming::kUr) {
      throw InputError({"--robot", 0, 0}, "tf exports every frame of the result, not one robot's",
                       "Leave out --robot (with tf it names the robot of --names ur)");
    }
    if (!output.empty()) CheckExportTarget(output, overwrite);  // before the work
    LoadPlugins(context);
    const CalibratedCell cell = ReadCalibratedCell(result_folder, Registry::Global());
    const std::string text = ExportText(cell, format, robot, Registry::Global(), naming);
    if (StopAfterCheck(output.empty() ? "to the standard output" : output)) return;
    if (output.empty()) {
      std::fputs(text.c_str(), stdout);
      return;
    }
    WriteExportFile(output, text, overwrite);
    if (!context.quiet) std::printf("written: %s (%s)\n", output.c_str(), format_name.c_str());
  });
}

}  // namespace cellmetry::app
