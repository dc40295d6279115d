// `cellmetry plugins`: every loaded plugin, its one-line description and its options.
#include <cstdio>

#include "cellmetry/registry/registry.h"
#include "commands.h"

namespace cellmetry::app {

void AddPluginsCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand("plugins", "list plugins with their options and units");
  cmd->callback([&context] {
    LoadPlugins(context);
    for (const auto& info : Registry::Global().List()) {
      std::printf("%-12s %-16s %s\n", KindName(info.kind).c_str(), info.name.c_str(),
                  info.description.c_str());
      for (const auto& option : info.options) {
        std::string detail = option.unit.empty() ? "" : "[" + option.unit + "] ";
        if (!option.default_value.empty()) detail += "(default " + option.default_value + ") ";
        std::printf("%31s%-22s %s%s\n", "", option.name.c_str(), detail.c_str(),
                    option.description.c_str());
      }
      std::printf("%31sfrom %s\n", "", info.library.c_str());
    }
  });
}

}  // namespace cellmetry::app
