// `cellmetry home JOB.yaml`: visual homing of a calibrated arm (homing.h).
#include <cstdio>

#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/homing_io.h"
#include "cellmetry/cell/homing_job.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/report/reports.h"
#include "commands.h"

namespace cellmetry::app {

void AddHomeCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand(
      "home", "visual homing: motor homing offsets from measured marker positions");
  static std::string job_path, output;
  cmd->add_option("job", job_path, "homing job (YAML, job: homing)")->required();
  cmd->add_option("-o,--output", output, "result folder (default: the job's `output`)");
  cmd->callback([&context] {
    Progress::SetQuiet(context.quiet);
    LoadPlugins(context);
    const HomingJob job = LoadHomingJob(job_path, Registry::Global());
    CheckReplaceable(output.empty() ? job.job.output : output, "homing");
    const std::vector<PointSample> samples = CollectPoints(job, ReadRecording(job.job.recording));
    if (StopAfterCheck(output.empty() ? job.job.output : output)) return;
    const HomingResult result = HomeVisually(job.arm, samples, job.sigma_mm, job.options);
    const std::string folder = output.empty() ? job.job.output : output;
    WriteHomingResult(result, folder, [&](const std::string& staging) {
      AtomicWriteFile(staging + "/" + report::kReportFile,
                      report::HomeReportHtml(result, "cellmetry home: " + job_path));
    });
    std::printf("%s", HomingSummary(result).c_str());
    std::printf("  written: %s/{homing.yaml,report.html}\n", folder.c_str());
  });
}

}  // namespace cellmetry::app
