// `cellmetry simulate SPEC.yaml -o FOLDER`: a simulated recording with its truth.yaml, from the
// one simulator (workcell_simulation.h) — a multi-robot workcell or a delta arm alike.
#include <cstdio>

#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/experiments/concealed_physics.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/imaging/image_simulation.h"
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
    const WorkcellSimulationSpec spec =
        LoadWorkcellSimulation(spec_path, Registry::Global(), ReadConcealedDisturbance);
    CheckReplaceable(output, "recording");  // before the work, not after it
    if (StopAfterCheck(output)) return;
    WorkcellTruth truth;
    Recording recording = SimulateWorkcell(spec, &truth);
    std::function<void(const std::string&)> images;
    if (spec.images) {
      // What the cameras see as pixels instead of measured poses: `cellmetry detect` measures.
      images = PlanImages(ReadImageRenderSpec(*spec.images, CameraNames(spec), TargetNames(spec),
                                              Registry::Global()),
                          WorkcellViews(spec, recording), spec.noise_seed, Registry::Global(),
                          &recording);
      recording.observations.clear();
    }
    WriteRecording(recording, output, TruthYaml(truth), images);
    std::printf("simulated %zu samples, %zu observations, %zu images -> %s (truth in truth.yaml)\n",
                recording.samples.size(), recording.observations.size(), recording.images.size(),
                output.c_str());
  });
}

}  // namespace cellmetry::app
