// `cellmetry run JOB.yaml`: identify the cell the job describes — a multi-robot workcell or a
// delta arm's kinematic calibration, one pipeline (workcell.h) — and write the result folder.
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/held_out_setup.h"
#include "cellmetry/cell/held_out_targets.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/result_io.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/report/reports.h"
#include "commands.h"

namespace cellmetry::app {
namespace {

void RunJob(const std::string& job_path, const std::string& output,
            const std::vector<std::string>& without) {
  Registry& registry = Registry::Global();
  WorkcellJob job = LoadWorkcellJob(job_path, registry);
  for (const std::string& camera : without) job.problem.cameras[camera].use = false;
  if (job.kind == "homing") {
    throw InputError({job_path, 0, 0}, "a homing job runs with 'cellmetry home'",
                     "Run: cellmetry home " + job_path);
  }
  const std::string folder = output.empty() ? job.output : output;
  CheckReplaceable(folder, "result");  // before the fit, not after it
  const Recording recording = ReadRecording(job.recording);
  for (const std::string& camera : without) {
    if (recording.HasCamera(camera)) continue;
    throw InputError({job_path, 0, 0},
                     "--without " + camera + ": no such camera in " + recording.folder,
                     "Name a camera as recording.yaml does");
  }
  ValidateJobAgainstRecording(job, recording);
  if (StopAfterCheck(folder)) return;
  const SolverMaker make_solver = [&] {
    return registry.CreateSolver(job.solver_type, *job.solver_config);
  };
  WorkcellResult result = IdentifyWorkcell(job.problem, recording, make_solver);
  if (job.validation_recording) {
    const Recording fresh = ReadRecording(*job.validation_recording);
    ValidateJobAgainstRecording(job, fresh);
    result.validation = ScoreOnRecording(job.problem, result, fresh);
  }
  std::optional<Recording> held_out;
  if (job.held_out_setup) {
    held_out = ReadRecording(job.held_out_setup->recording);
    const Recording& other_setup = *held_out;
    ValidateJobAgainstRecording(job, other_setup);
    Progress::Note("held-out setup: registering the frames again and scoring " +
                   other_setup.folder);
    result.held_out_setup =
        ScoreHeldOutSetup(job.problem, result, recording, other_setup,
                          SelectRegistrationPoses(other_setup, job.held_out_setup->register_on,
                                                  job.held_out_setup_where),
                          make_solver);
  }
  WriteWorkcellResult(result, folder, [&](const std::string& staging) {
    AtomicWriteFile(staging + "/" + report::kReportFile,
                    report::RunReportHtml(result, recording, "cellmetry run: " + job_path));
    if (held_out)
      WriteHeldOutSetupFolder(*result.held_out_setup, *held_out, staging + "/held_out_setup");
  });
  std::printf("%s", WorkcellSummary(result).c_str());
  std::printf("  written: %s/{result.yaml,result.json,residuals.csv,report.html}\n",
              folder.c_str());
}

}  // namespace

void AddRunCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand("run",
                                     "identify a cell: base frames, tools, cameras and "
                                     "whatever robot geometry the job frees");
  static std::string job_path;
  static std::string output;
  static std::vector<std::string> without;
  cmd->add_option("job", job_path, "job file (YAML)")->required();
  cmd->add_option("-o,--output", output, "result folder (default: the job's `output`)");
  cmd->add_option("--without", without,
                  "a camera to leave out whole, as `cameras: {<camera>: {use: false}}` does "
                  "(repeat for more)");
  cmd->callback([&context] {
    Progress::SetQuiet(context.quiet);
    LoadPlugins(context);
    RunJob(job_path, output, without);
  });
}

}  // namespace cellmetry::app
