// Helpers shared by the test suites.
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/diagnosis/pose_plan.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry::testing {

// The global registry with the plugins of this build loaded (once).
Registry& Plugins();

// Absolute path of a file in the source tree, e.g. Source("tests/data/vsb/sim_b").
std::string Source(const std::string& relative);

// A fresh, empty temporary folder for one test.
std::string TempDir(const std::string& name);
// TempDir("<folder>/<name of the running test>").
std::string TempDirForThisTest(const std::string& folder);

// Writes `text` to `path` (creating folders).
void WriteText(const std::string& path, const std::string& text);
std::string ReadText(const std::string& path);

// Replaces the one occurrence of `from` in `text`; fails the test if it is not there once.
std::string ReplaceOnce(const std::string& text, const std::string& from, const std::string& to);

// Replaces line `line` (1-based) of the file at `path`.
void EditLine(const std::string& path, int line, const std::string& replacement);

struct CommandResult {
  int exit_code = 0;
  std::string output;  // stdout and stderr together
};

// Runs `action`, which must raise InputError, and returns the error (a test failure if it does
// not).
template <typename Action>
InputError CatchInputError(Action action) {
  try {
    action();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError";
  return InputError({}, "no error raised");
}

// The job's own solver, as `cellmetry run` makes it; and the job's identification of `recording`.
SolverMaker JobSolver(const WorkcellJob& job);
WorkcellResult Identify(const WorkcellJob& job, const Recording& recording);

// The frame called `name` in `result` (throws when there is none).
const FrameEstimate& Frame(const WorkcellResult& result, const std::string& name);

// The job `noise:` of the two static cameras of configs/simulations/ur3_two_cameras.yaml and
// ur3_physics_base.yaml (their simulated scatter), one line.
extern const char kTwoCameraNoiseYaml[];

// configs/jobs/ur3_diagnose.yaml written into `dir` with an absolute robot path, loaded, with 30
// bootstrap resamples (quicker, still stable); and the physics finder's diagnosis of
// `recording` with that job's solver and candidates.
DiagnosisJob Ur3DiagnoseJob(const std::string& dir);

// The UR3 cell of configs/simulations/ur3_two_cameras.yaml without noise, its tool board printed
// `scale` large (target_scale), written as a recording in `dir`/rec; the spec is the truth.
WorkcellSimulationSpec SimulateScaledToolBoard(const std::string& dir, double scale);

// Hides a compliance of joint 3 (4e-5 rad/Nm unless said, the UR3's link masses) in `spec`'s
// first robot: the library effect the physics-finder tests conceal most. A negative one is a
// joint that gives against gravity: no physics, a stand-in for a look-alike.
void ConcealJoint3Compliance(WorkcellSimulationSpec* spec, double compliance = 4e-5);
// The same at `joint` (1-based), `compliance` rad/Nm.
void ConcealJointCompliance(WorkcellSimulationSpec* spec, int joint, double compliance);
DiagnosisResult Diagnose(const DiagnosisJob& job, const Recording& recording,
                         const std::string& origin);
// The poses `cellmetry plan` proposes for `job` on `recording`: the cell identified without
// cross-validation, then PlanPoses with the job's candidates.
PosePlan Plan(const DiagnosisJob& job, const Recording& recording, const PosePlanOptions& options);

// Runs the built `cellmetry` binary with `arguments` (a shell-quoted string).
CommandResult RunCellmetry(const std::string& arguments);

// The contract for bad input through the CLI: exit code 2 and one line
// "<location> error: ... <text> ..." (location e.g. "job.yaml:12:1:").
void ExpectOneLineError(const CommandResult& result, const std::string& location,
                        const std::string& text);

}  // namespace cellmetry::testing
