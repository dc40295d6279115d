// A diverged fit is an error, not a result: a solver that ends on a non-finite parameter (or
// cost) stops the identification where it ends, with a message naming the parameter, instead of
// writing NaN into result.yaml with exit 0 or crashing in the covariance after it.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

// Ends with the first free parameter not a number, as an exploding gradient step would.
class DivergingSolver : public Solver {
 public:
  SolverSummary Solve(Problem& problem) override {
    Eigen::VectorXd x = problem.FreeValues();
    x[0] = std::numeric_limits<double>::quiet_NaN();
    problem.SetFreeValues(x);
    SolverSummary summary;
    summary.solver = "diverging";
    summary.final_cost = 1.0;
    return summary;
  }
};

TEST(DivergedFit, IsAnErrorNamingTheParameterNotAResult) {
  WorkcellJob job =
      LoadWorkcellJob(testing::Source("configs/jobs/vsb_sim_b.yaml"), testing::Plugins());
  job.problem.folds = 0;
  const Recording recording = ReadRecording(job.recording);
  try {
    IdentifyWorkcell(job.problem, recording, [] { return std::make_unique<DivergingSolver>(); });
    FAIL() << "a diverged fit came back as a result";
  } catch (const InputError& e) {
    EXPECT_THAT(e.message(), ::testing::HasSubstr("the fit diverged (diverging): "));
    EXPECT_THAT(e.message(), ::testing::HasSubstr("is not a number"));
    EXPECT_THAT(e.hint(), ::testing::HasSubstr("nothing was written"));
  }
}

}  // namespace
}  // namespace cellmetry
