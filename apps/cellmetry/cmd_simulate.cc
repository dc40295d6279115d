#include "commands.h"
namespace cellmetry::app {
void AddSimulateCommand(CLI::App&, Context&) {}
}  // namespace cellmetry::app
