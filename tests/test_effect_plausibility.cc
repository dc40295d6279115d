// A job's effect fitted beyond the size its physics plausibly has is a warning of the run
// (workcell.cc, AddImplausibleEffectWarnings): a board printed 5 % off is fitted at 5 % (beyond
// target_scale's plausible 2 %) and the run says so, naming the parameter; at 0.5 % it does not.
#include <gtest/gtest.h>

#include <algorithm>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/formats/recording.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

// The UR3 cell of configs/simulations/ur3_two_cameras.yaml without noise, its tool board printed
// `scale` large, identified with the target_scale effect free.
WorkcellResult FitScaledBoard(const std::string& dir, double scale) {
  testing::SimulateScaledToolBoard(dir, scale);
  const std::string job =
      "job: workcell\nrecording: " + dir + "/rec\n"
      "robots:\n  ur3:\n    model: " + testing::Source("configs/robots/ur3.yaml") +
      "\n    base: {free: all}\n    tools:\n      tool: {free: [x, y, z]}\n"
      "effects:\n  - {type: target_scale, targets: [tool]}\n" +
      testing::kTwoCameraNoiseYaml + "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n";
  testing::WriteText(dir + "/job.yaml", job);
  return testing::Identify(LoadWorkcellJob(dir + "/job.yaml", testing::Plugins()),
                           ReadRecording(dir + "/rec"));
}

bool WarnsAbout(const WorkcellResult& result, const std::string& parameter) {
  return std::any_of(result.warnings.begin(), result.warnings.end(), [&](const std::string& w) {
    return w.find(parameter) != std::string::npos && w.find("plausibly") != std::string::npos;
  });
}

TEST(EffectPlausibility, AnEffectFittedBeyondItsPhysicsIsAWarning) {
  const WorkcellResult result =
      FitScaledBoard(testing::TempDirForThisTest("implausible_board"), 0.05);
  EXPECT_TRUE(WarnsAbout(result, "target_scale.tool.scale"));
}

TEST(EffectPlausibility, APlausibleSizeIsNoWarning) {
  const WorkcellResult result =
      FitScaledBoard(testing::TempDirForThisTest("plausible_board"), 0.005);
  EXPECT_FALSE(WarnsAbout(result, "target_scale"));
}

}  // namespace
}  // namespace cellmetry
