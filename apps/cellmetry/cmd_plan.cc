// `cellmetry plan JOB.yaml`: the joint poses to record next, chosen so that what the physics
// finder calls untestable becomes testable and the free parameters are best determined
// (pose_plan.h). Identifies the cell first; writes <output>/plan/{plan.csv,plan.txt}.
#include <cstdio>
#include <vector>

#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/camera_left_out.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/diagnosis/pose_plan.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/recording.h"
#include "commands.h"

namespace cellmetry::app {

void AddPlanCommand(CLI::App& app, Context& context) {
  CLI::App* cmd =
      app.add_subcommand("plan",
                         "propose joint poses that make untestable effects testable, or tell two "
                         "candidates apart (D-optimal)");
  static std::string job_path, output;
  static PosePlanOptions options;
  cmd->add_option("job", job_path, "workcell job (YAML), as for diagnose")->required();
  cmd->add_option("-n,--poses", options.poses, "how many poses to propose")
      ->check(CLI::Range(1, 10000));
  cmd->add_option("--draws", options.draws, "random joint poses to choose among")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--effect", options.effects,
                  "a candidate to plan for (e.g. ur3.compliance_j2), repeated for several (the "
                  "diagnose report names a pair to tell apart); default: every one the recorded "
                  "poses leave untestable");
  cmd->add_option("-o,--output", output, "plan folder (default: <job output>/plan)");
  cmd->callback([&context] {
    Progress::SetQuiet(context.quiet);
    LoadPlugins(context);
    Registry& registry = Registry::Global();
    const DiagnosisJob job = LoadDiagnosisJob(job_path, registry);
    const std::string folder = output.empty() ? job.workcell.output + "/plan" : output;
    CheckReplaceable(folder, "plan");  // before the work, not after it
    const Recording read = ReadRecording(job.workcell.recording);
    ValidateJobAgainstRecording(job.workcell, read);
    // The candidates and the poses' views are the cameras the job uses.
    const Recording recording = WithoutCameras(read, UnusedCameras(job.workcell.problem));
    const SolverMaker make_solver = [&] {
      return registry.CreateSolver(job.workcell.solver_type, *job.workcell.solver_config);
    };
    const std::vector<CandidateEffect> candidates = JobCandidates(job, recording, registry);
    CheckNamedEffects(candidates, options);  // before the identification, not after it
    if (StopAfterCheck(folder)) return;
    WorkcellProblem problem = job.workcell.problem;
    problem.folds = 0;  // the plan needs the answer, not its held-out score, nor each camera's
    problem.leave_one_camera_out = false;
    Progress::Note("identifying the cell on the recorded poses");
    const WorkcellResult fitted = IdentifyWorkcell(problem, recording, make_solver);
    Progress::Note("choosing poses");
    const PosePlan plan = PlanPoses(problem, recording, fitted, candidates, options);
    StagedDirectory out(folder, "plan");
    AtomicWriteFile(out.File("plan.csv"), PosePlanCsv(plan));
    AtomicWriteFile(out.File("plan.txt"), PosePlanReport(plan));
    out.Commit();
    std::printf("%s  written: %s/{plan.csv,plan.txt}\n", PosePlanReport(plan).c_str(),
                folder.c_str());
  });
}

}  // namespace cellmetry::app
