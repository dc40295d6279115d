// `cellmetry simulate SPEC.yaml -o FOLDER`: a simulated recording with its truth.yaml.
#include <cstdio>

#include "cellmetry/experiments/concealed_physics.h"
#include "cellmetry/imaging/image_simulation.h"
#include "cellmetry/cell/kinematic_simulation.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/workcell_simulation.h"
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
    const ConfigNode root = ConfigNode::LoadFile(spec_path);
    const std::string kind = root["simulation"].AsString();
    Recording recording;
    if (kind == "workcell") {
      const WorkcellSimulationSpec spec = LoadWorkcellSimulation(spec_path, Registry::Global(), ReadConcealedDisturbance);
      WorkcellTruth truth;
      recording = SimulateWorkcell(spec, &truth);
      std::function<void(const std::string&)> images;
      if (spec.images) {
        // What the cameras see as pixels instead of measured poses: `cellmetry detect` measures.
        images = PlanImages(ReadImageRenderSpec(*spec.images, CameraNames(spec), TargetNames(spec),
                                                Registry::Global()),
                            WorkcellViews(spec, recording), spec.seed, Registry::Global(),
                            &recording);
        recording.observations.clear();
      }
      WriteRecording(recording, output, TruthYaml(truth), images);
    } else if (kind == "kinematic") {
      const KinematicSimulationSpec spec = LoadKinematicSimulation(spec_path, Registry::Global());
      std::mt19937 truth_rng(spec.seed), rng(spec.pose_seed);
      const KinematicState truth = DrawTruth(spec, truth_rng);
      const auto commands = MakePoseSet(spec, spec.pose_set, spec.count, rng);
      recording = SimulateKinematic(spec, truth, commands, rng);
      std::function<void(const std::string&)> images;
      if (spec.images) {
        // The camera's view as pixels instead of measured points: `cellmetry detect` measures.
        const std::vector<SampleView> views = MarkerViews(spec, truth, recording);
        images = PlanImages(ReadImageRenderSpec(*spec.images, {spec.camera}, {spec.target},
                                                Registry::Global()),
                            views, spec.pose_seed, Registry::Global(), &recording);
        recording.observations.clear();
      }
      WriteRecording(recording, output, TruthYaml(KinematicTruthRecord(spec, truth)), images);
    } else {
      throw root["simulation"].Error("unknown simulation kind '" + kind + "'",
                                     "Use workcell or kinematic");
    }
    std::printf("simulated %zu samples, %zu observations, %zu images -> %s (truth in truth.yaml)\n",
                recording.samples.size(), recording.observations.size(),
                recording.images.size(), output.c_str());
  });
}

}  // namespace cellmetry::app
