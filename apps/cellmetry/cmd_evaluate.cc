// `cellmetry evaluate RESULT_FOLDER TRUTH.yaml`: each estimate's error against the truth, in
// its unit and in its own sigma.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/formats/workcell_result_file.h"
#include "commands.h"

namespace cellmetry::app {

void AddEvaluateCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand("evaluate", "compare a result with a simulation's truth");
  static std::string result_folder, truth_path;
  cmd->add_option("result", result_folder,
                  "result folder written by `cellmetry run` (or its result.json)")
      ->required();
  cmd->add_option("truth", truth_path, "truth.yaml of the simulated recording")->required();
  cmd->callback([] {
    // The folder, or the result.json in it: both name the same result.
    const std::filesystem::path given(result_folder);
    const std::string json_path =
        given.filename() == "result.json" && !std::filesystem::is_directory(given)
            ? given.string()
            : (given / "result.json").string();
    // A result that is not there is a job not run yet.
    if (!std::ifstream(json_path)) {
      throw InputError({json_path, 0, 0}, "cannot open result", "Run the job first");
    }
    const WorkcellResultFile result = ReadWorkcellResult(json_path);
    const WorkcellEvaluation evaluation =
        EvaluateWorkcell(result, ReadTruth(truth_path), truth_path);
    if (StopAfterCheck("nothing (evaluate prints)")) return;
    std::printf("%-28s %14s %12s %10s\n", "quantity", "error", "sigma", "error/sigma");
    bool gauge = false;
    for (const auto& q : evaluation.quantities) {
      if (q.combination && !gauge) {
        std::printf(
            "in a gauge: the data determines these combinations (the held parameter at "
            "nominal, its error carried by its partner):\n");
        gauge = true;
      }
      std::printf("%-28s %11.6f %-3s %11.6f %10.2f%s\n", q.name.c_str(), q.error, q.unit.c_str(),
                  q.sigma, q.normalized(), q.in_gauge ? "  (in a gauge: see below)" : "");
    }
    std::printf("largest error: %.6f mm, %.3g rad; largest |error/sigma|: %.2f\n",
                evaluation.max_translation_error_mm, evaluation.max_rotation_error_rad,
                evaluation.max_abs_normalized);
  });
}

}  // namespace cellmetry::app
