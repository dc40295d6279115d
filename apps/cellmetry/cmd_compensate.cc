// `cellmetry compensate RESULT_DIR TARGETS.csv [-o FILE] [--robot NAME] [--tool NAME] ...`: the
// joint commands that reach target poses under a result's calibrated geometry and effects
// (compensation.h). Without -o the commands go to standard output. A file is written only where
// nothing is, or over an earlier cellmetry output (kept as FILE.previous); a user's file only
// with --overwrite (export_file.h). Exit code 3 when a target is refused, unless
// --allow-refused; the commands of the others are written either way.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "cellmetry/compensation/commands_csv.h"
#include "cellmetry/compensation/compensation.h"
#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/exports/export_file.h"
#include "commands.h"

namespace cellmetry::app {
namespace {

// Each refused target on standard error, one line: "TARGETS.csv:12: target 'p3' refused: ...".
int ReportRefused(const std::string& targets_path,
                  const std::vector<CompensatedCommand>& commands) {
  int refused = 0;
  for (const auto& c : commands) {
    if (!c.refused) continue;
    ++refused;
    std::fprintf(stderr, "%s:%d: target '%s' refused: %s\n", targets_path.c_str(), c.target->line,
                 c.target->id.c_str(), c.reason.c_str());
  }
  return refused;
}

// One line on standard error when commands go beyond the calibration's joint ranges: they are
// not refused (the robot can reach them), but their error is extrapolated.
void ReportBeyondCalibration(const std::vector<CompensatedCommand>& commands) {
  int beyond = 0;
  for (const auto& c : commands) beyond += c.joints_beyond_calibration.empty() ? 0 : 1;
  if (beyond == 0) return;
  std::fprintf(stderr,
               "note: %d of %zu commands put a joint beyond the ranges the calibration's poses "
               "span (column beyond_calibration): there the calibrated model is extrapolated; "
               "calibrate over the ranges the robot works in\n",
               beyond, commands.size());
}

// CLI::Range lets "nan" through: every comparison with it is false.
CLI::Validator Finite() {
  return CLI::Validator(
      [](std::string& text) {
        const double value = std::strtod(text.c_str(), nullptr);
        return std::isfinite(value) ? std::string() : "Value " + text + " is not a finite number";
      },
      "FINITE");
}

}  // namespace

void AddCompensateCommand(CLI::App& app, Context& context) {
  CLI::App* cmd =
      app.add_subcommand("compensate",
                         "turn target tool poses (or joint targets) into the joint commands that "
                         "reach them under a result's calibrated geometry and effects");
  static std::string result_folder, targets_path, robot, tool, output;
  static bool overwrite = false, allow_refused = false;
  static CompensationOptions options;
  cmd->add_option("result", result_folder,
                  "result folder (`cellmetry run`, or a diagnosis's "
                  "final_fit/ with its accepted effects)")
      ->required();
  cmd->add_option("targets", targets_path, "TARGETS.csv (docs/formats.md)")->required();
  cmd->add_option("--robot", robot, "the robot (default: the result's only one)");
  cmd->add_option("--tool", tool,
                  "the tool the targets are for: a tool frame of the result, or "
                  "'flange' (default: the robot's only tool)");
  cmd->add_option("-o,--output", output, "commands CSV to write (default: standard output)");
  // A tolerance of 0 or less is never met and 0 iterations never move from the seed: either
  // calls every reachable target out of reach. The upper ends are beyond any arm's work.
  cmd->add_option("--tolerance-mm", options.tolerance_mm, "a target is reached within this")
      ->capture_default_str()
      ->check(Finite())
      ->check(CLI::Range(1e-9, 100.0));
  cmd->add_option("--tolerance-rad", options.tolerance_rad, "and within this rotation")
      ->capture_default_str()
      ->check(Finite())
      ->check(CLI::Range(1e-12, 0.1));
  cmd->add_option("--max-iterations", options.max_iterations, "solver iterations per target")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--joint-limit-margin-rad", options.joint_limit_margin_rad,
                  "refuse commands this close to a joint limit")
      ->capture_default_str()
      ->check(Finite())
      ->check(CLI::Range(0.0, 3.2));
  cmd->add_flag("--allow-refused", allow_refused,
                "exit 0 even when targets are refused (they are listed in the file)");
  cmd->add_flag("--overwrite", overwrite,
                "replace a file cellmetry did not write (it is kept as FILE.previous)");
  cmd->callback([&context] {
    if (!output.empty()) CheckExportTarget(output, overwrite);  // before the work
    LoadPlugins(context);
    const CalibratedCell cell = ReadCalibratedCell(result_folder, Registry::Global());
    const CompensationChain chain = ChainFromResult(cell, robot, tool);
    const auto targets = ReadCompensationTargets(targets_path, chain.model->num_joints());
    if (StopAfterCheck(output.empty() ? "to the standard output" : output)) return;
    const auto commands = Compensate(chain, targets, cell.covariance, options);
    const std::string text =
        CompensatedCommandsCsv(chain, commands, CompensationComments(cell, chain));
    if (output.empty()) {
      std::fputs(text.c_str(), stdout);
    } else {
      WriteExportFile(output, text, overwrite);
    }
    const int refused = ReportRefused(targets_path, commands);
    ReportBeyondCalibration(commands);
    if (!context.quiet && !output.empty()) {
      std::printf("written: %s (%zu commands, %d refused)\n", output.c_str(),
                  commands.size() - refused, refused);
    }
    if (refused > 0 && !allow_refused) context.exit_code = kRefusedTargetsExitCode;
  });
}

}  // namespace cellmetry::app
