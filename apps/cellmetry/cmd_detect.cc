// `cellmetry detect JOB.yaml`: run a detector over a recording's images (detection.h).
#include <cstdio>

#include "cellmetry/basics/progress.h"
#include "cellmetry/imaging/detection.h"
#include "commands.h"

namespace cellmetry::app {

void AddDetectCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand(
      "detect", "find markers in a recording's images and write its observations (resumable)");
  static std::string job_path;
  static int limit = 0;
  cmd->add_option("job", job_path, "detect job (YAML, job: detect)")->required();
  cmd->add_option("--limit", limit,
                  "stop after this many new images (the next run continues; 0: no limit)")
      ->check(CLI::Range(0, 1000000000));
  cmd->callback([&context] {
    Progress::SetQuiet(context.quiet);
    LoadPlugins(context);
    const DetectJob job = LoadDetectJob(job_path, Registry::Global());
    if (StopAfterCheck(job.recording + "/observations.csv")) return;
    const DetectSummary s = RunDetection(job, Registry::Global(), limit);
    std::string detectors;
    for (const auto& marker : job.targets) {
      detectors += (detectors.empty() ? "" : ", ") + marker.target + ": " + marker.detector_type;
    }
    std::printf("Detection (%s) in %s\n", detectors.c_str(), job.recording.c_str());
    std::printf("  %d images; (image, target) pairs: %d done before, %d done now; %d found\n",
                s.images, s.already_done, s.processed, s.found);
    for (const auto& [reason, count] : s.failures) {
      std::printf("  not found in %d: %s\n", count, reason.c_str());
    }
    std::printf("  observations.csv: %d observations; per image: detections.jsonl\n",
                s.observations);
  });
}

}  // namespace cellmetry::app
