// cellmetry: camera-based robot metrology from the command line.
//
// Exit codes: 0 success, 2 bad input (InputError: file:line:column: error: what. hint),
// 1 anything else (a bug: please report it).
#include <cstdio>
#include <filesystem>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/registry/registry.h"
#include "commands.h"

namespace cellmetry::app {

namespace {
bool g_check_only = false;
}  // namespace

void SetCheckOnly(bool check_only) { g_check_only = check_only; }

bool StopAfterCheck(const std::string& would_write) {
  if (!g_check_only) return false;
  std::printf("checked: every input reads; would write %s\n", would_write.c_str());
  return true;
}

void LoadPlugins(const Context& context) {
  Registry& registry = Registry::Global();
  registry.LoadDefaultFolders(context.executable);
  for (const auto& folder : context.plugin_paths) {
    // A mistyped folder loaded nothing without a word; the job then failed on an "unknown"
    // plugin type far from the cause, or ran without the plugin meant.
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec)) {
      throw InputError({"--plugin-path", 0, 0}, "no plugin folder at '" + folder + "'",
                       "Point --plugin-path at the folder that holds the plugin libraries");
    }
    registry.LoadFolder(folder);
  }
}

namespace {

// CLI11 answers an unknown command word with "A subcommand is required": name the word. (Only
// when no word is a command: --plugin-path takes any number of folders.)
void RefuseUnknownCommand(const CLI::App& cli, int argc, char** argv) {
  std::string known, unknown;
  for (const CLI::App* sub : cli.get_subcommands({})) {
    known += (known.empty() ? "" : ", ") + sub->get_name();
  }
  bool after_plugin_path = false;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    for (const CLI::App* sub : cli.get_subcommands({})) {
      if (sub->get_name() == word) return;
    }
    if (!word.empty() && word[0] == '-') {
      after_plugin_path = word == "--plugin-path";
    } else if (!after_plugin_path && unknown.empty()) {
      unknown = word;
    }
  }
  if (unknown.empty()) return;
  throw InputError({"cellmetry", 0, 0}, "'" + unknown + "' is not a cellmetry command",
                   "Use one of: " + known);
}

}  // namespace

}  // namespace cellmetry::app

int main(int argc, char** argv) {
  using namespace cellmetry;
  app::Context context;
  context.executable = argv[0];
  CLI::App cli{"cellmetry: camera-based robot metrology (workcell layout, robot calibration)"};
  cli.require_subcommand(1);
  cli.add_option("--plugin-path", context.plugin_paths, "extra folder to load plugins from")
      ->type_name("DIR");
  cli.add_flag("-q,--quiet", context.quiet, "no progress output");
  cli.add_flag_callback(
      "--check", [] { app::SetCheckOnly(true); },
      "load and check every input, say what would be written, and stop before the work "
      "(nothing is written)");
  cli.add_flag_callback(
      "-v,--verbose", [] { Progress::SetVerbose(true); },
      "progress of nested work and its notes too (a fit's folds inside a comparison's seeds)");
  app::AddRunCommand(cli, context);
  app::AddSimulateCommand(cli, context);
  app::AddEvaluateCommand(cli, context);
  app::AddHomeCommand(cli, context);
  app::AddCompareCommand(cli, context);
  app::AddDetectCommand(cli, context);
  app::AddDiagnoseCommand(cli, context);
  app::AddPlanCommand(cli, context);
  app::AddExportCommand(cli, context);
  app::AddCompensateCommand(cli, context);
  app::AddImportCommand(cli, context);
  app::AddCalibrateCameraCommand(cli, context);
  app::AddPluginsCommand(cli, context);
  try {
    app::RefuseUnknownCommand(cli, argc, argv);
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = cli.exit(e);
    return code == 0 ? 0 : kInputErrorExitCode;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return kInputErrorExitCode;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cellmetry: internal error: %s\n", e.what());
    return 1;
  }
  return context.exit_code;
}
