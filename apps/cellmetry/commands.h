// The `cellmetry` subcommands. Each Add*Command registers its options on `app` and a callback
// that does the work; errors propagate as exceptions and main() turns them into exit codes.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace cellmetry::app {

struct Context {
  std::string executable;                 // argv[0], to find the plugins folder
  std::vector<std::string> plugin_paths;  // --plugin-path
  bool quiet = false;
  int exit_code = 0;  // what main returns when no exception ended the command
};

// `cellmetry compensate` refused a target (its commands file lists why).
inline constexpr int kRefusedTargetsExitCode = 3;

// `cellmetry --check <command> ...`: every input the command reads has been loaded and checked
// by now; StopAfterCheck says so and what the command would write, and returns true, and the
// command stops before its work, writing nothing. Without --check it returns false.
bool StopAfterCheck(const std::string& would_write);
void SetCheckOnly(bool check_only);

// Loads the default plugin folders plus --plugin-path ones into the global registry.
void LoadPlugins(const Context& context);

void AddRunCommand(CLI::App& app, Context& context);
void AddPluginsCommand(CLI::App& app, Context& context);
void AddSimulateCommand(CLI::App& app, Context& context);
void AddEvaluateCommand(CLI::App& app, Context& context);
void AddHomeCommand(CLI::App& app, Context& context);
void AddCompareCommand(CLI::App& app, Context& context);
void AddDetectCommand(CLI::App& app, Context& context);
void AddDiagnoseCommand(CLI::App& app, Context& context);
void AddPlanCommand(CLI::App& app, Context& context);
void AddExportCommand(CLI::App& app, Context& context);
void AddCompensateCommand(CLI::App& app, Context& context);
void AddImportCommand(CLI::App& app, Context& context);
void AddCalibrateCameraCommand(CLI::App& app, Context& context);

}  // namespace cellmetry::app
