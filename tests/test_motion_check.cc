// Degenerate recordings named, not fitted into numbers (motion_check.h): every pose at one
// command is an error at samples.csv; a joint whose reading never changes, and a solver that
// stopped before converging, are warnings that reach result.json and the summary. The cell is
// sim_b (tests/data/vsb/sim_b) with its samples altered.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/motion_check.h"
#include "cellmetry/cell/result_io.h"
#include "cellmetry/cell/workcell.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

WorkcellJob SimB() {
  WorkcellJob job =
      LoadWorkcellJob(testing::Source("configs/jobs/vsb_sim_b.yaml"), testing::Plugins());
  job.problem.folds = 0;
  job.problem.leave_one_camera_out = false;
  return job;
}

SolverMaker JobSolver(const WorkcellJob& job) {
  return [&job] { return testing::Plugins().CreateSolver(job.solver_type, *job.solver_config); };
}

bool Warns(const WorkcellResult& result, const std::string& text) {
  for (const std::string& w : result.warnings) {
    if (w.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(MotionCheck, EveryPoseAtOneCommandIsAnErrorAtSamplesCsv) {
  const WorkcellJob job = SimB();
  Recording recording = ReadRecording(job.recording);
  for (Sample& s : recording.samples) s.q = recording.samples.front().q;
  try {
    IdentifyWorkcell(job.problem, recording, JobSolver(job));
    FAIL() << "a robot that never moved was fitted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.message(), HasSubstr("samples of robot 'ur3' that the fit uses has the same "
                                       "joint readings"));
    EXPECT_THAT(e.where().file, HasSubstr("samples.csv"));
    EXPECT_GT(e.where().line, 1);
    EXPECT_THAT(e.hint(), HasSubstr("Record poses that move the robot"));
  }
}

TEST(MotionCheck, AJointThatNeverMovesIsAWarningInTheResult) {
  const WorkcellJob job = SimB();
  Recording recording = ReadRecording(job.recording);
  for (Sample& s : recording.samples) s.q[0] = recording.samples.front().q[0];  // stuck encoder
  const WorkcellResult result = IdentifyWorkcell(job.problem, recording, JobSolver(job));
  const std::string still = "joint 1 of ur3 reads";
  EXPECT_TRUE(Warns(result, still)) << WorkcellSummary(result);
  EXPECT_THAT(WorkcellResultJson(result)["warnings"].dump(), HasSubstr(still));
  EXPECT_THAT(WorkcellSummary(result), HasSubstr(still));
  // The recording as it is moves every joint: no such warning.
  const WorkcellResult as_recorded =
      IdentifyWorkcell(job.problem, ReadRecording(job.recording), JobSolver(job));
  EXPECT_FALSE(Warns(as_recorded, "reads")) << WorkcellSummary(as_recorded);
  EXPECT_FALSE(Warns(as_recorded, "stopped before converging")) << WorkcellSummary(as_recorded);
}

// Stops where it starts, as a solver at its iteration limit from a far start would.
class StoppingSolver : public Solver {
 public:
  SolverSummary Solve(Problem&) override {
    SolverSummary summary;
    summary.solver = "stopping";
    summary.converged = false;
    summary.stop_reason = "iteration limit reached";
    return summary;
  }
};

TEST(MotionCheck, ASolverStoppedBeforeConvergingIsAWarningInTheResult) {
  const WorkcellJob job = SimB();
  const WorkcellResult result = IdentifyWorkcell(job.problem, ReadRecording(job.recording),
                                                 [] { return std::make_unique<StoppingSolver>(); });
  const std::string stopped = "the solver stopped before converging (iteration limit reached)";
  EXPECT_TRUE(Warns(result, stopped)) << WorkcellSummary(result);
  EXPECT_THAT(WorkcellResultJson(result)["warnings"].dump(), HasSubstr(stopped));
}

}  // namespace
}  // namespace cellmetry
