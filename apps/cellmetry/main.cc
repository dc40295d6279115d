// cellmetry: camera-based robot metrology from the command line.
//
// Exit codes: 0 success, 2 bad input (InputError: file:line:column: error: what. hint),
// 1 anything else (a bug: please report it).
#include <cstdio>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/registry/registry.h"
#include "commands.h"

namespace cellmetry::app {

void LoadPlugins(const Context& context) {
  Registry& registry = Registry::Global();
  registry.LoadDefaultFolders(context.executable);
  for (const auto& folder : context.plugin_paths) registry.LoadFolder(folder);
}

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
  app::AddPluginsCommand(cli, context);
  try {
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
