// A job's effect fitted beyond the size its physics plausibly has is a warning of the run
// (workcell_warnings.cc, AddImplausibleEffectWarnings): a board printed 5 % off is fitted at
// 5 % (beyond target_scale's plausible 2 %) and the run says so, naming the parameter; at 0.5 %
// it does not.
// So is a compliance fitted well below zero (a joint giving against gravity), and not one at +.
#include <gtest/gtest.h>

#include <algorithm>

#include "cellmetry/basics/plausibility.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/formats/recording.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

// A UR3 job on `dir`/rec, its base free and `robot_lines` after it (tools, effects), `job_lines`
// before the robots, written to `dir`/job.yaml and identified.
WorkcellResult FitUr3(const std::string& dir, const std::string& robot_lines,
                      const std::string& job_lines = "") {
  const std::string job =
      "job: workcell\nrecording: " + dir + "/rec\n" + job_lines +
      "robots:\n  ur3:\n    model: " + testing::Source("configs/robots/ur3_vsb2020.yaml") +
      "\n    base: {free: all}\n" + robot_lines + testing::kTwoCameraNoiseYaml +
      "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n";
  testing::WriteText(dir + "/job.yaml", job);
  return testing::Identify(LoadWorkcellJob(dir + "/job.yaml", testing::Plugins()),
                           ReadRecording(dir + "/rec"));
}

// The UR3 cell of configs/simulations/ur3_two_cameras.yaml without noise, its tool board printed
// `scale` large, identified with the target_scale effect free.
WorkcellResult FitScaledBoard(const std::string& dir, double scale) {
  testing::SimulateScaledToolBoard(dir, scale);
  return FitUr3(dir, "    tools:\n      tool: {free: [x, y, z]}\n",
                "effects:\n  - {type: target_scale, targets: [tool]}\n");
}

// The physics suite's UR3 cell (payload alternating: compliance testable) with a joint 3
// compliance of `compliance` hidden, fitted with joint 3 compliance free.
WorkcellResult FitJoint3Compliance(const std::string& dir, double compliance) {
  std::string sim = testing::ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml"));
  sim = testing::ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml",
                             testing::Source("configs/robots/ur3_vsb2020.yaml"));
  testing::WriteText(dir + "/sim.yaml", sim);
  WorkcellSimulationSpec spec = LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins());
  testing::ConcealJoint3Compliance(&spec, compliance);
  WriteRecording(SimulateWorkcell(spec, nullptr), dir + "/rec", "");
  return FitUr3(dir,
                "    tools:\n      tool: {free: all}\n    effects:\n"
                "      - {type: joint_compliance, joints: [3], "
                "link_masses_kg: [2.0, 3.42, 1.26, 0.8, 0.8, 0.35]}\n",
                "use_tool_rotation: true\n");
}

// A warning naming `parameter` that says `why` ("plausibly": its size; "below zero": its sign).
bool Warns(const WorkcellResult& result, const std::string& parameter, const std::string& why) {
  return std::any_of(result.warnings.begin(), result.warnings.end(), [&](const std::string& w) {
    return w.find(parameter) != std::string::npos && w.find(why) != std::string::npos;
  });
}

TEST(EffectPlausibility, AnEffectFittedBeyondItsPhysicsIsAWarning) {
  const WorkcellResult result =
      FitScaledBoard(testing::TempDirForThisTest("implausible_board"), 0.05);
  EXPECT_TRUE(Warns(result, "target_scale.tool.scale", "plausibly"));
}

TEST(EffectPlausibility, AComplianceFittedBelowZeroIsAWarning) {
  const WorkcellResult against =
      FitJoint3Compliance(testing::TempDirForThisTest("against_gravity"), -4e-5);
  EXPECT_TRUE(Warns(against, "j3.compliance", "below zero"));
  const WorkcellResult with =
      FitJoint3Compliance(testing::TempDirForThisTest("with_gravity"), 4e-5);
  EXPECT_FALSE(Warns(with, "j3.compliance", "below zero"));
  EXPECT_FALSE(Warns(with, "j3.compliance", "plausibly"));
}

TEST(EffectPlausibility, APlausibleSizeIsNoWarning) {
  const WorkcellResult result =
      FitScaledBoard(testing::TempDirForThisTest("plausible_board"), 0.005);
  EXPECT_FALSE(Warns(result, "target_scale", "plausibly"));
}

// Several cameras' principal points are judged as what they share (within 0.05 rad: a cause
// common to cameras calibrated alike) and each one's own part (within 0.02 rad): experiment A's
// (1, -13), (14, -30), (-18, -14) mrad share -19 mrad in y and depart by at most 17 mrad, so
// nothing is unusual, though cam2's y alone would be. One camera alone is judged by its own
// bound; a shift shared beyond 0.05 rad is named as the shared part.
TEST(GroupedPlausibility, CamerasPrincipalPointsJudgedAsTheirSharedShiftAndEachOnesOwn) {
  const auto ur3 = testing::Plugins().CreateRobotModel(
      "serial_mdh", ConfigNode::LoadFile(testing::Source("configs/robots/ur3_vsb2020.yaml")));
  const ConfigNode three = ConfigNode::LoadString(
      "{type: camera_intrinsics, cameras: [cam1, cam2, cam3], terms: [principal]}", "test");
  const auto effect = testing::Plugins().CreateEffect("camera_intrinsics", three, *ur3);
  const std::vector<Parameter>& parameters = effect->parameters();
  ASSERT_EQ(parameters.size(), 6u);
  EXPECT_TRUE(
      JudgePlausibility(parameters, {0.0012, -0.0127, 0.0144, -0.0301, -0.0175, -0.0141}).empty());
  const auto shared = JudgePlausibility(parameters, {0.0, -0.07, 0.0, -0.06, 0.0, -0.065});
  ASSERT_EQ(shared.size(), 1u);
  EXPECT_EQ(shared[0].part, PlausibilityFinding::Part::kCommon);
  EXPECT_NEAR(shared[0].mean, -0.065, 1e-12);
  const auto own = JudgePlausibility(parameters, {0.0, 0.0, 0.03, 0.0, -0.01, 0.0});
  ASSERT_EQ(own.size(), 1u);
  EXPECT_EQ(own[0].part, PlausibilityFinding::Part::kDeparture);
  EXPECT_EQ(parameters[own[0].index].name, "cam2.principal_x");
  EXPECT_NE(PlausibilityText(parameters, {0.0, 0.0, 0.03, 0.0, -0.01, 0.0}, own[0])
                .find("cam2.principal_x = 0.03 rad, 0.0233 off the 0.00667"),
            std::string::npos);

  const ConfigNode one = ConfigNode::LoadString(
      "{type: camera_intrinsics, cameras: [cam2], terms: [principal]}", "test");
  const auto alone = testing::Plugins().CreateEffect("camera_intrinsics", one, *ur3);
  const auto found = JudgePlausibility(alone->parameters(), {0.0144, -0.0301});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].part, PlausibilityFinding::Part::kValue);
  EXPECT_EQ(alone->parameters()[found[0].index].name, "cam2.principal_y");
}

}  // namespace
}  // namespace cellmetry
