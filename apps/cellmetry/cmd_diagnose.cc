// `cellmetry diagnose JOB.yaml`: the physics finder (diagnosis.h) on a workcell job.
#include <cstdio>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/camera_left_out.h"
#include "cellmetry/cell/held_out_setup.h"
#include "cellmetry/cell/held_out_targets.h"
#include "cellmetry/cell/joint_ranges.h"
#include "cellmetry/cell/result_io.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/checkpoint.h"
#include "cellmetry/report/reports.h"
#include "commands.h"

namespace cellmetry::app {
namespace {

// The job's held-out setup (validation.held_out_setup), scored with the geometry alone and with
// the accepted effects, every value from the diagnosed recording: the final fit's result carries
// the latter; the line says both.
std::string ScoreHeldOutSetups(const WorkcellJob& job, const Recording& recording,
                               const SolverMaker& make_solver, const Recording& other_setup,
                               DiagnosisResult* result) {
  ValidateJobAgainstRecording(job, other_setup);
  const std::vector<int> poses = SelectRegistrationPoses(
      other_setup, job.held_out_setup->register_on, job.held_out_setup_where);
  Progress::Note("held-out setup: the geometry alone, then with the accepted effects");
  WorkcellProblem geometry = job.problem;
  geometry.folds = 0;
  geometry.leave_one_camera_out = false;
  const HeldOutSetupScore alone =
      ScoreHeldOutSetup(geometry, IdentifyWorkcell(geometry, recording, make_solver), recording,
                        other_setup, poses, make_solver);
  result->final_fit.held_out_setup = ScoreHeldOutSetup(result->final_spec, result->final_fit,
                                                       recording, other_setup, poses, make_solver);
  const HeldOutSetupScore& with = *result->final_fit.held_out_setup;
  char line[600];
  std::snprintf(line, sizeof line,
                "Held-out setup (%s, frames registered again on %zu poses, %d scored): "
                "geometry alone %.4f +- %.4f mm, with the accepted effects %.4f +- %.4f mm "
                "(nominal %.4f mm; the effects gain %.4f +- %.4f mm, paired); "
                "%.1f %% within their 95 %% ellipsoid.\n",
                with.recording.c_str(), with.registration_poses.size(), with.scored_poses,
                alone.rms_mm, alone.rms_se_mm, with.rms_mm, with.rms_se_mm, with.nominal_rms_mm,
                alone.rms_mm - with.rms_mm, RmsGainStandardError(alone, with),
                100.0 * with.within_95);
  const std::string beyond = BeyondCalibrationText(with);
  return beyond.empty() ? std::string(line) : std::string(line) + "  " + beyond + "\n";
}

// What a diagnosis's checkpoint is keyed by: the job's text, its robots' model files, the
// recording's files and the cameras left out. An edit to any of them starts over.
std::string DiagnosisFingerprint(const std::string& job_path, const DiagnosisJob& job,
                                 const Recording& recording,
                                 const std::vector<std::string>& without) {
  std::string inputs = FileFingerprint(job_path) + " " + FolderFingerprint(recording.folder);
  for (const WorkcellRobot& robot : job.workcell.problem.robots) {
    inputs += " " + std::to_string(std::hash<std::string>{}(robot.model_config));
  }
  for (const std::string& camera : without) inputs += " without " + camera;
  return std::to_string(std::hash<std::string>{}(inputs));
}

}  // namespace

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
    if (StopAfterCheck(folder)) return;
    const SolverMaker make_solver = [&] {
      return registry.CreateSolver(job.workcell.solver_type, *job.workcell.solver_config);
    };
    // Finished rounds kept beside the output: an interrupted diagnosis resumes where it stopped.
    const std::string checkpoint_path = folder + ".partial.json";
    Checkpoint checkpoint(checkpoint_path, DiagnosisFingerprint(job_path, job, read, without));
    DiagnosisResult result = DiagnoseWorkcell(job.workcell.problem, recording, make_solver,
                                              JobCandidates(job, recording, registry), job.options,
                                              job_path, &checkpoint);
    std::optional<Recording> other_setup;
    std::string held_out_line;
    if (job.workcell.held_out_setup) {
      other_setup = ReadRecording(job.workcell.held_out_setup->recording);
      held_out_line =
          ScoreHeldOutSetups(job.workcell, recording, make_solver, *other_setup, &result);
    }
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
      if (other_setup) {
        WriteHeldOutSetupFolder(*result.final_fit.held_out_setup, *other_setup,
                                staging + "/held_out_setup");
      }
    });
    out.Commit();
    std::filesystem::remove(checkpoint_path);
    std::printf("%s%s", DiagnosisReport(result).c_str(), held_out_line.c_str());
    std::printf("  written: %s/{report.txt,report.html,diagnosis.json,final_fit/}\n",
                folder.c_str());
  });
}

}  // namespace cellmetry::app
