// `cellmetry diagnose JOB.yaml`: the physics finder (diagnosis.h) on a workcell job.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>
#include <nlohmann/json.hpp>

#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/report/reports.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/camera_left_out.h"
#include "cellmetry/cell/result_io.h"
#include "commands.h"

namespace cellmetry::app {

void AddDiagnoseCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand(
      "diagnose", "find the physics a workcell's geometric model leaves out (effects)");
  static std::string job_path, output;
  static std::vector<std::string> without;
  cmd->add_option("job", job_path, "workcell job (YAML), with an optional diagnosis: section")
      ->required();
  cmd->add_option("-o,--output", output, "folder (default: <job output>/diagnosis)");
  cmd->add_option("--without", without,
                  "a camera to leave out whole, as `cameras: {<camera>: {use: false}}` does "
                  "(repeat for more)");
  cmd->callback([&context] {
    Progress::SetQuiet(context.quiet);
    LoadPlugins(context);
    Registry& registry = Registry::Global();
    DiagnosisJob job = LoadDiagnosisJob(job_path, registry);
    const std::string folder = output.empty() ? job.workcell.output + "/diagnosis" : output;
    CheckReplaceable(folder, "diagnosis");  // before the work, not after it
    const Recording read = ReadRecording(job.workcell.recording);
    for (const std::string& camera : without) {
      if (!read.HasCamera(camera)) {
        throw InputError({job_path, 0, 0},
                         "--without " + camera + ": no such camera in " + read.folder,
                         "Name a camera as recording.yaml does");
      }
      job.workcell.problem.cameras[camera].use = false;
    }
    ValidateJobAgainstRecording(job.workcell, read);
    // The finder's candidates and linearizations are made from the cameras the job uses.
    const Recording recording = WithoutCameras(read, UnusedCameras(job.workcell.problem));
    const SolverMaker make_solver = [&] {
      return registry.CreateSolver(job.workcell.solver_type, *job.workcell.solver_config);
    };
    const DiagnosisResult result =
        DiagnoseWorkcell(job.workcell.problem, recording, make_solver,
                         JobCandidates(job, recording, registry), job.options, job_path);
    StagedDirectory out(folder, "diagnosis");
    AtomicWriteFile(out.File("diagnosis.json"), DiagnosisJson(result).dump(2) + "\n");
    AtomicWriteFile(out.File("report.txt"), DiagnosisReport(result));
    AtomicWriteFile(
        out.File(report::kReportFile),
        report::DiagnoseReportHtml(result, recording, "cellmetry diagnose: " + job_path));
    WriteWorkcellResult(result.final_fit, out.File("final_fit"), [&](const std::string& staging) {
      AtomicWriteFile(staging + "/" + report::kReportFile,
                      report::RunReportHtml(result.final_fit, recording,
                                            "cellmetry diagnose, final fit: " + job_path));
    });
    out.Commit();
    std::printf("%s", DiagnosisReport(result).c_str());
    std::printf("  written: %s/{report.txt,report.html,diagnosis.json,final_fit/}\n",
                folder.c_str());
  });
}

}  // namespace cellmetry::app
