// `cellmetry run JOB.yaml`: run the job the file describes (its `job:` kind) and write the
// result folder.
#include <cstdio>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/cell/result_io.h"
#include "cellmetry/cell/workcell.h"
#include "commands.h"

namespace cellmetry::app {
namespace {

void RunWorkcellJob(const std::string& job_path, const std::string& output) {
  Registry& registry = Registry::Global();
  const WorkcellJob job = LoadWorkcellJob(job_path, registry);
  const Recording recording = ReadRecording(job.recording);
  ValidateJobAgainstRecording(job, recording);
  const SolverMaker make_solver = [&] {
    return registry.CreateSolver(job.solver_type, *job.solver_config);
  };
  const WorkcellResult result = IdentifyWorkcell(job.problem, recording, make_solver);
  const std::string folder = output.empty() ? job.output : output;
  WriteWorkcellResult(result, folder);
  std::printf("%s", WorkcellSummary(result).c_str());
  std::printf("  written: %s/{result.yaml,result.json,residuals.csv}\n", folder.c_str());
}

}  // namespace

void AddRunCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand("run", "run a job: workcell identification or kinematic calibration");
  static std::string job_path;
  static std::string output;
  cmd->add_option("job", job_path, "job file (YAML)")->required();
  cmd->add_option("-o,--output", output, "result folder (default: the job's `output`)");
  cmd->callback([&context] {
    Progress::SetQuiet(context.quiet);
    LoadPlugins(context);
    const ConfigNode root = ConfigNode::LoadFile(job_path);
    const std::string kind = root["job"].AsString();
    if (kind == "workcell") {
      RunWorkcellJob(job_path, output);
    } else if (kind == "kinematic") {
      RunKinematicJob(job_path, output);
    } else if (kind == "homing") {
      throw root["job"].Error("a homing job runs with 'cellmetry home'",
                              "Run: cellmetry home " + job_path);
    } else {
      throw root["job"].Error("unknown job kind '" + kind + "'",
                              "Use workcell, kinematic (cellmetry run) or homing (cellmetry home)");
    }
  });
}

}  // namespace cellmetry::app
