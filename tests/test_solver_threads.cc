// A solve the core runs beside other work of its own is limited to the machine's cores but one
// (solver.h, LeavingOneCore), and the ceres_lm plugin comes to the same answer however many
// threads it is given.
#include <gtest/gtest.h>

#include <thread>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_initial.h"
#include "cellmetry/estimation/noise_model.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

// Solves nothing; says how many threads it would use where its own option asks for `wanted`.
class ThreadProbe : public Solver {
 public:
  SolverSummary Solve(Problem&) override { return {}; }
  int Threads(int wanted) const { return ThreadsWithinLimit(wanted); }
};

TEST(SolverThreads, ALimitCapsTheSolversOwnOptionAndNoLimitKeepsIt) {
  ThreadProbe probe;
  EXPECT_EQ(probe.Threads(2), 2);
  probe.LimitThreads(1);
  EXPECT_EQ(probe.Threads(2), 1);
  probe.LimitThreads(8);
  EXPECT_EQ(probe.Threads(2), 2);  // a limit never adds threads
}

TEST(SolverThreads, LeavingOneCoreLeavesOneOfTheMachinesCoresAndAtLeastOneThread) {
  const SolverMaker limited = LeavingOneCore([] { return std::make_unique<ThreadProbe>(); });
  const std::unique_ptr<Solver> solver = limited();
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  EXPECT_EQ(static_cast<ThreadProbe&>(*solver).Threads(64), std::max(1, cores - 1));
}

// sim_b's cell, assembled at its closed-form start.
struct AssembledSimB {
  WorkcellJob job;
  Recording recording;
  WorkcellData data;
  NoiseModel noise;
  std::unique_ptr<AssembledWorkcell> assembled;
};

std::unique_ptr<AssembledSimB> AssembleSimB() {
  auto c = std::make_unique<AssembledSimB>();
  c->job = LoadWorkcellJob(testing::Source("configs/jobs/vsb_sim_b.yaml"), testing::Plugins());
  c->recording = ReadRecording(c->job.recording);
  c->data = PrepareWorkcellData(c->job.problem, c->recording);
  c->noise = BuildNoiseModel(c->recording, c->job.problem.noise);
  const WorkcellEstimate start = InitialEstimate(c->job.problem, c->recording, c->data);
  c->assembled = AssembleWorkcell(c->job.problem, c->recording, c->data, c->noise, start);
  return c;
}

TEST(SolverThreads, CeresLmOnOneThreadComesToTheAnswerOfItsTwo) {
  Eigen::VectorXd answer[2];
  for (int limit : {0, 1}) {
    const std::unique_ptr<AssembledSimB> cell = AssembleSimB();
    std::unique_ptr<Solver> solver = testing::Plugins().CreateSolver(
        "ceres_lm", ConfigNode::LoadString("type: ceres_lm\nthreads: 2", "test"));
    solver->LimitThreads(limit);
    const SolverSummary summary = solver->Solve(cell->assembled->problem);
    ASSERT_TRUE(summary.converged) << summary.stop_reason;
    answer[limit] = cell->assembled->problem.FreeValues();
  }
  ASSERT_EQ(answer[0].size(), answer[1].size());
  for (Eigen::Index i = 0; i < answer[0].size(); ++i) {
    EXPECT_NEAR(answer[1][i], answer[0][i], 1e-9 * std::max(1.0, std::abs(answer[0][i])))
        << "parameter " << i;
  }
}

}  // namespace
}  // namespace cellmetry
