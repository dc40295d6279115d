// The pose planner (pose_plan.h): on a simulated UR3 cell whose recorded poses keep joint 1
// within 0.05 rad, the finder calls joint 1's gear ratio error untestable (the geometry absorbs
// it); the planned poses make it testable, and recorded too, the finder then names it.
#include <gtest/gtest.h>

#include <algorithm>

#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/diagnosis/pose_plan.h"
#include "cellmetry/import/importer.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

class PosePlanning : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDirForThisTest("pose_plan");
    std::string sim =
        testing::ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml"));
    sim = testing::ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml",
                               testing::Source("configs/robots/ur3_vsb2020.yaml"));
    sim = testing::ReplaceOnce(sim, "random: 150", "random: 60");
    sim = testing::ReplaceOnce(sim, "lower: [-6.2,", "lower: [0.5,");  // joint 1 barely moves
    sim = testing::ReplaceOnce(sim, "upper: [6.2,", "upper: [0.55,");
    testing::WriteText(dir_ + "/sim.yaml", sim);
    spec_ = LoadWorkcellSimulation(dir_ + "/sim.yaml", testing::Plugins());
    const ConfigNode gear = ConfigNode::LoadString("{type: joint_scale, joints: [1]}", "test");
    SimulatedEffect e;
    e.name = "ur3.joint_scale";
    e.effect = testing::Plugins().CreateEffect("joint_scale", gear, *spec_.robots[0].model);
    e.values = {1e-3};  // 0.1 % of the gear ratio
    spec_.robots[0].effects.push_back(e);
    job_ = testing::Ur3DiagnoseJob(dir_);
  }

  DiagnosisResult Diagnose(const Recording& recording) const {
    return testing::Diagnose(job_, recording, dir_ + "/job.yaml");
  }

  std::string dir_;
  WorkcellSimulationSpec spec_;
  DiagnosisJob job_;
};

bool Untestable(const DiagnosisResult& d, const std::string& name) {
  return std::any_of(d.untestable.begin(), d.untestable.end(),
                     [&](const CandidateFinding& f) { return f.name == name; });
}

TEST_F(PosePlanning, PlannedPosesMakeAnAbsorbedGearRatioTestableAndItIsThenFound) {
  const Recording recorded = SimulateWorkcell(spec_, nullptr);
  // Joint 1 barely moves: its 0.1 % gear ratio error is almost all a turn of the base, which the
  // finder cannot name from these poses (untestable, or too weak to pass its tests).
  const DiagnosisResult before = Diagnose(recorded);
  for (const auto& a : before.accepted)
    EXPECT_NE(a.name, "ur3.scale_j1") << DiagnosisReport(before);

  PosePlanOptions options;
  options.poses = 15;
  const PosePlan plan = testing::Plan(job_, recorded, options);
  ASSERT_EQ(plan.poses.size(), 15u);
  const auto gear = std::find_if(plan.effects.begin(), plan.effects.end(),
                                 [](const PlannedEffect& e) { return e.name == "ur3.scale_j1"; });
  ASSERT_NE(gear, plan.effects.end()) << PosePlanReport(plan);
  EXPECT_LT(gear->unabsorbed_before, 0.05);
  EXPECT_GT(gear->unabsorbed_after, 0.2) << PosePlanReport(plan);
  const RobotLimits& limits = spec_.robots[0].model->limits();
  for (const auto& pose : plan.poses) {
    EXPECT_FALSE(pose.cameras.empty());
    for (size_t j = 0; j < pose.q.size() && j < limits.joint_min_rad.size(); ++j) {
      EXPECT_GE(pose.q[j], limits.joint_min_rad[j]);
      EXPECT_LE(pose.q[j], limits.joint_max_rad[j]);
    }
  }

  // Record the plan too: the same cell, the planned poses after the recorded ones.
  WorkcellSimulationSpec extended = spec_;
  for (const auto& pose : plan.poses) extended.robots[0].joint_poses.push_back(pose.q);
  const DiagnosisResult after = Diagnose(SimulateWorkcell(extended, nullptr));
  EXPECT_FALSE(Untestable(after, "ur3.scale_j1"));
  ASSERT_FALSE(after.accepted.empty()) << DiagnosisReport(after);
  EXPECT_EQ(after.accepted.front().name, "ur3.scale_j1") << DiagnosisReport(after);
}

// The real TX90L (tests/data/astl), every MDH entry free: the plan holds what the identification
// held (joint 1's entries, the flange's, ...), so the sigma it predicts are the data's, not the
// parametrisation's null directions (before, 1e9 and more). Joint 5's compliance against its
// transmission error, the finder's next candidate there: the planned poses tell them further
// apart and halve the compliance's sigma.
TEST(PosePlanOnRealData, TrackerCellWithEveryMdhEntryFreeGetsFiniteSigma) {
  const DiagnosisJob job =
      LoadDiagnosisJob(testing::Source("configs/jobs/staubli_tx90l_diagnose.yaml"),
                       testing::Plugins(), /*recording_must_exist=*/false);
  const Recording calibration =
      ImportRecording(testing::Source("configs/import/astl_calibration.yaml"));
  PosePlanOptions options;
  options.poses = 20;
  options.draws = 500;
  options.effects = {"tx90l.compliance_j5", "tx90l.transmission_j5"};
  const PosePlan plan = testing::Plan(job, calibration, options);
  ASSERT_EQ(plan.poses.size(), 20u);
  for (const PlannedSigma& s : plan.sigma) {
    EXPECT_LT(s.before, 1.0) << s.name << "\n" << PosePlanReport(plan);
    EXPECT_LE(s.after, s.before * 1.0001) << s.name;
  }
  ASSERT_EQ(plan.effects.size(), 2u);
  const PlannedEffect& compliance =
      plan.effects[0].name == "tx90l.compliance_j5" ? plan.effects[0] : plan.effects[1];
  ASSERT_EQ(compliance.sigma.size(), 1u);
  EXPECT_LT(compliance.sigma[0].before, 1e-4) << PosePlanReport(plan);  // rad/(N m)
  EXPECT_LT(compliance.sigma[0].after, 0.7 * compliance.sigma[0].before) << PosePlanReport(plan);
  ASSERT_EQ(plan.pairs.size(), 1u);
  EXPECT_LT(plan.pairs[0].correlation_after, plan.pairs[0].correlation_before);
}

}  // namespace
}  // namespace cellmetry
