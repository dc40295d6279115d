// Gross outliers (outliers.h): with +20 mm on the tool's measured position in 2 % of the poses
// of a simulated two-camera UR3 cell, no base or tool coordinate moves by more than its clean
// sigma, and the bad observations are the ones listed; on clean data nothing is listed and the
// answer is the plain fit's. (At 10 % of the poses the plain fit that the test starts from is
// pulled so far that the outliers' residuals hide in the inflated scale: that needs a robust
// first fit, not built yet.)
#include <gtest/gtest.h>

#include <set>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

class Outliers : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string dir = testing::TempDirForThisTest("outliers");
    std::string sim =
        testing::ReadText(testing::Source("configs/simulations/ur3_two_cameras.yaml"));
    sim = testing::ReplaceOnce(sim, "../robots/ur3.yaml", testing::Source("configs/robots/ur3.yaml"));
    sim = testing::ReplaceOnce(sim, "../../tests/data/vsb/sim_b",
                               testing::Source("tests/data/vsb/sim_b"));
    testing::WriteText(dir + "/sim.yaml", sim);
    clean_ = SimulateWorkcell(LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins()),
                              nullptr);
    testing::WriteText(
        dir + "/job.yaml",
        "job: workcell\nrecording: " + dir + "/none\nrobots:\n  ur3:\n    model: " +
            testing::Source("configs/robots/ur3.yaml") +
            "\n    base: {free: all}\n    tools:\n      tool: {free: [x, y, z]}\n" +
            testing::kTwoCameraNoiseYaml + "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n");
    job_ = LoadWorkcellJob(dir + "/job.yaml", testing::Plugins(), false);
  }

  WorkcellResult Identify(const Recording& recording) const {
    return testing::Identify(job_, recording);
  }

  Recording clean_;
  WorkcellJob job_;
};

TEST_F(Outliers, GrossErrorsInTwoPercentOfPosesMoveNothingByMoreThanItsCleanSigma) {
  const WorkcellResult clean = Identify(clean_);
  EXPECT_TRUE(clean.outliers.empty()) << clean.outliers.size() << " flagged on clean data";

  Recording corrupted = clean_;
  std::set<int> bad_samples;
  for (const auto& s : corrupted.samples) {
    if (s.pose % 50 == 3) bad_samples.insert(s.id);  // 2 % of the poses
  }
  for (auto& obs : corrupted.observations) {
    if (obs.target == "tool" && bad_samples.count(obs.sample)) obs.position_mm.x() += 20.0;
  }
  const WorkcellResult r = Identify(corrupted);
  std::set<int> flagged;
  for (const auto& o : r.outliers) flagged.insert(o.sample);
  EXPECT_EQ(flagged, bad_samples);
  for (const char* name : {"ur3.base", "tool"}) {
    const FrameEstimate& a = testing::Frame(clean, name);
    const FrameEstimate& b = testing::Frame(r, name);
    for (int i = 0; i < 3; ++i) {
      if (a.held[i]) continue;
      EXPECT_LE(std::abs(b.pose.t[i] - a.pose.t[i]), a.sigma_mm[i])
          << name << " " << "xyz"[i] << ": " << a.pose.t[i] << " -> " << b.pose.t[i];
    }
  }
}

}  // namespace
}  // namespace cellmetry
