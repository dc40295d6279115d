// The pose planner on the case it exists for: on a simulated UR3 whose recorded
// poses hold the shoulder and elbow in one configuration (joints 2 and 3 within 0.02 rad) and
// the wrist's joints 4 and 5 within 0.1 rad while the base and the last wrist joint turn, under
// a constant payload, joint 2's gravity load does not change from pose to pose: its compliance
// is a constant joint 2 angle, which the free joint 2 offset absorbs, and the finder calls it
// untestable. (With joints 4 and 5 turning too, the wrist's masses vary the load enough to leave
// 7 % of the signature outside the geometry: "testable", and not found at this size.) The
// planned poses swing the shoulder and elbow, inside the joint limits, where the cameras have
// seen the tool; recorded with the same concealed compliance, the finder names it, with the
// sigma the plan predicted.
#include <gtest/gtest.h>

#include <algorithm>

#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/diagnosis/pose_plan.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

constexpr double kCompliance = 3e-5;  // rad/(N m): 0.4 mrad at the UR3's ~13 N m on joint 2

// ur3_physics_base.yaml with the shoulder and elbow held, the wrist's first two joints nearly
// held, and a constant payload; joint 2's compliance (the job's link masses) concealed in it.
WorkcellSimulationSpec ShoulderHeldCell(const std::string& dir) {
  std::string sim = testing::ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml"));
  sim = testing::ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml",
                             testing::Source("configs/robots/ur3_vsb2020.yaml"));
  sim = testing::ReplaceOnce(sim, "random: 150", "random: 60");
  sim = testing::ReplaceOnce(sim, "lower: [-6.2, 2.4, -2.2, -6.2, -6.2, -6.2]",
                             "lower: [-6.2, 3.3, -1.0, -1.6, 1.5, -6.2]");
  sim = testing::ReplaceOnce(sim, "upper: [6.2, 4.2, 2.2, 6.2, 6.2, 6.2]",
                             "upper: [6.2, 3.32, -0.98, -1.5, 1.6, 6.2]");
  sim = testing::ReplaceOnce(sim, "payloads_kg: [0, 1.0]", "payloads_kg: [0.5]");
  testing::WriteText(dir + "/sim.yaml", sim);
  WorkcellSimulationSpec spec = LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins());
  testing::ConcealJointCompliance(&spec, 2, kCompliance);
  return spec;
}

// The UR3 diagnosis job with the joint offsets a calibration frees (joints 2 and 3: joint 1's
// is the base's rotation, the wrist's are held by these poses as well as by the tool's).
DiagnosisJob JobWithJointOffsets(const std::string& dir) {
  std::string job = testing::ReadText(testing::Source("configs/jobs/ur3_diagnose.yaml"));
  job = testing::ReplaceOnce(job, "model: ../robots/ur3_vsb2020.yaml",
                             "model: " + testing::Source("configs/robots/ur3_vsb2020.yaml"));
  job = testing::ReplaceOnce(job, "    base: {free: all}\n",
                             "    base: {free: all}\n    free_model: [j2.offset, j3.offset]\n");
  testing::WriteText(dir + "/job.yaml", job);
  DiagnosisJob loaded = LoadDiagnosisJob(dir + "/job.yaml", testing::Plugins(), false);
  loaded.options.bootstrap = 30;
  return loaded;
}

const CandidateFinding* Untestable(const DiagnosisResult& d, const std::string& name) {
  for (const auto& f : d.untestable) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

TEST(PosePlanCompliance, PlannedPosesMakeAnAbsorbedComplianceTestableAndItIsThenFound) {
  const std::string dir = testing::TempDirForThisTest("pose_plan_compliance");
  const WorkcellSimulationSpec spec = ShoulderHeldCell(dir);
  const DiagnosisJob job = JobWithJointOffsets(dir);
  const Recording recorded = SimulateWorkcell(spec, nullptr);

  // Before: absorbed by the joint 2 offset, so untestable, and not named.
  const DiagnosisResult before = testing::Diagnose(job, recorded, dir + "/job.yaml");
  const CandidateFinding* absorbed = Untestable(before, "ur3.compliance_j2");
  ASSERT_NE(absorbed, nullptr) << DiagnosisReport(before);
  EXPECT_LT(absorbed->unabsorbed, 0.05);
  EXPECT_NE(absorbed->untestable_because.find("absorbed by the geometry"), std::string::npos);
  EXPECT_NE(absorbed->data_needed.find("load joint 2 differently"), std::string::npos);
  for (const auto& a : before.accepted) EXPECT_NE(a.name, "ur3.compliance_j2");

  PosePlanOptions options;
  options.poses = 15;
  const PosePlan plan = testing::Plan(job, recorded, options);
  ASSERT_EQ(plan.poses.size(), 15u);
  const auto planned = std::find_if(plan.effects.begin(), plan.effects.end(),
                                    [](const auto& e) { return e.name == "ur3.compliance_j2"; });
  ASSERT_NE(planned, plan.effects.end()) << PosePlanReport(plan);
  EXPECT_LT(planned->unabsorbed_before, 0.05);
  EXPECT_GT(planned->unabsorbed_after, 0.2) << PosePlanReport(plan);
  // Its predicted sigma: undetermined before (the offset's direction), a sixth of its size after.
  ASSERT_EQ(planned->sigma.size(), 1u);
  EXPECT_EQ(planned->sigma[0].name, "ur3.compliance_j2.j2.compliance");
  EXPECT_GT(planned->sigma[0].before, kCompliance) << PosePlanReport(plan);
  EXPECT_LT(planned->sigma[0].after, kCompliance / 4) << PosePlanReport(plan);
  EXPECT_GT(planned->sigma[0].before, 10 * planned->sigma[0].after);
  const auto offset = std::find_if(plan.sigma.begin(), plan.sigma.end(),
                                   [](const auto& s) { return s.name == "ur3.model.j2.offset"; });
  ASSERT_NE(offset, plan.sigma.end());
  EXPECT_LT(offset->after, offset->before);  // the shoulder's swing determines it too
  const RobotLimits& limits = spec.robots[0].model->limits();
  bool shoulder_swings = false;
  for (const auto& pose : plan.poses) {
    EXPECT_FALSE(pose.cameras.empty());
    for (size_t j = 0; j < pose.q.size() && j < limits.joint_min_rad.size(); ++j) {
      EXPECT_GE(pose.q[j], limits.joint_min_rad[j]);
      EXPECT_LE(pose.q[j], limits.joint_max_rad[j]);
    }
    shoulder_swings |= std::abs(pose.q[1] - 3.31) > 0.3 || std::abs(pose.q[2] + 0.99) > 0.3;
  }
  EXPECT_TRUE(shoulder_swings);

  // After: the same cell and concealed compliance, the planned poses recorded after the others.
  WorkcellSimulationSpec extended = spec;
  for (const auto& pose : plan.poses) extended.robots[0].joint_poses.push_back(pose.q);
  const DiagnosisResult after =
      testing::Diagnose(job, SimulateWorkcell(extended, nullptr), dir + "/job.yaml");
  EXPECT_EQ(Untestable(after, "ur3.compliance_j2"), nullptr);
  ASSERT_FALSE(after.accepted.empty()) << DiagnosisReport(after);
  const AcceptedEffect& found = after.accepted.front();
  ASSERT_EQ(found.name, "ur3.compliance_j2") << DiagnosisReport(after);
  ASSERT_EQ(found.parameters.size(), 1u);
  const ScalarEstimate& c = found.parameters[0];
  EXPECT_NEAR(c.value, kCompliance, 3 * c.sigma) << DiagnosisReport(after);
  // Its statistical sigma is the one the plan predicted (the fit's scatter is at the floor; the
  // total adds the spread between the two cameras' solutions, which the plan cannot foresee).
  EXPECT_NEAR(c.sigma_statistical / planned->sigma[0].after, 1.0, 0.25)
      << c.sigma_statistical << " against " << planned->sigma[0].after;
}

}  // namespace
}  // namespace cellmetry
