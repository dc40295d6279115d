// `cellmetry simulate SPEC.yaml -o FOLDER`: a simulated recording with its truth.yaml.
#include <cstdio>

#include "cellmetry/progress.h"
#include "cellmetry/workcell_simulation.h"
#include "commands.h"

namespace cellmetry::app {

void AddSimulateCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand(
      "simulate", "write a simulated recording (and truth.yaml) from a simulation spec");
  static std::string spec_path, output;
  cmd->add_option("spec", spec_path, "simulation spec (YAML, see docs/formats.md)")->required();
  cmd->add_option("-o,--output", output, "recording folder to write")->required();
  cmd->callback([&context] {
    Progress::SetQuiet(context.quiet);
    LoadPlugins(context);
    const WorkcellSimulationSpec spec = LoadWorkcellSimulation(spec_path, Registry::Global());
    WorkcellTruth truth;
    const Recording recording = SimulateWorkcell(spec, &truth);
    WriteRecording(recording, output, TruthYaml(truth));
    std::printf("simulated %zu samples, %zu observations -> %s (truth in truth.yaml)\n",
                recording.samples.size(), recording.observations.size(), output.c_str());
  });
}

}  // namespace cellmetry::app
