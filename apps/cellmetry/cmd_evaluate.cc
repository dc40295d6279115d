#include "commands.h"
namespace cellmetry::app {
void AddEvaluateCommand(CLI::App&, Context&) {}
}  // namespace cellmetry::app
