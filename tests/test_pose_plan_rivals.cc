// The pose planner against a rival (issue 13): where the finder's closest candidate passes every
// test but the rival test (another effect explains the data nearly as well), the report
// proposes `cellmetry plan --effect <it> --effect <the rival>`, and the poses it plans tell them
// apart. The case: the physics suite's joint 2 compliance at SNR 6 (ur3_physics_base.yaml, its
// size and one of its noise seeds), where the finder stays silent: the compliance is its closest
// candidate, but were joint 2's transmission error the cause, its margin would come 3.3 % of
// the time (alpha 1 %). The 30 poses planned for the two, recorded with the same hidden
// compliance, make it name the compliance. (Over the suite's first ten seeds the finder names
// it in 3, docs/physics.md; of the silent seeds tried here, 30 planned poses resolve 4 of 8.)
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/diagnosis/pose_plan.h"
#include "cellmetry/report/reports.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

constexpr double kCompliance = 4.96e-6;  // rad/(N m): the suite's size for an unabsorbed SNR of 6
constexpr unsigned kSeed = 1004;         // the suite's 4th seed of the case

// ur3_physics_base.yaml with joint 2's compliance (the job's link masses) hidden in it, the
// recording's noise drawn from `kSeed` as the physics suite draws it.
WorkcellSimulationSpec Joint2ComplianceCell(const std::string& dir) {
  std::string sim = testing::ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml"));
  sim = testing::ReplaceOnce(sim, "../robots/ur3.yaml", testing::Source("configs/robots/ur3.yaml"));
  testing::WriteText(dir + "/sim.yaml", sim);
  WorkcellSimulationSpec spec = LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins());
  spec.seed = kSeed;
  spec.noise_seed = kSeed;
  testing::ConcealJointCompliance(&spec, 2, kCompliance);
  return spec;
}

// The last round's closest candidate, which failed some test (null when none did).
const CandidateFinding* Closest(const DiagnosisResult& d) {
  if (d.rounds.empty()) return nullptr;
  for (const auto& f : d.rounds.back().candidates) {
    if (!f.failed.empty()) return &f;
  }
  return nullptr;
}

TEST(PosePlanRivals, PosesPlannedForTheClosestCandidateAndItsRivalLetTheFinderName) {
  const std::string dir = testing::TempDirForThisTest("pose_plan_rivals");
  const WorkcellSimulationSpec spec = Joint2ComplianceCell(dir);
  DiagnosisJob job = testing::Ur3DiagnoseJob(dir);
  job.options.bootstrap = 40;  // the suite's
  const Recording recorded = SimulateWorkcell(spec, nullptr);

  // Before: silent. The closest candidate, the compliance, fails the rival test alone, against
  // joint 2's transmission error (and the bootstrap, which no longer gates, includes it in fewer
  // than 80 % of its resamples).
  const DiagnosisResult before = testing::Diagnose(job, recorded, dir + "/job.yaml");
  EXPECT_TRUE(before.accepted.empty()) << DiagnosisReport(before);
  const CandidateFinding* closest = Closest(before);
  ASSERT_NE(closest, nullptr) << DiagnosisReport(before);
  EXPECT_EQ(closest->name, "ur3.compliance_j2");
  EXPECT_EQ(closest->failed, std::vector<std::string>{"rivals"});
  EXPECT_GE(closest->rival_p, job.options.alpha);
  EXPECT_EQ(closest->rival_effect, "ur3.transmission_j2");
  EXPECT_LT(closest->bootstrap_share, 0.8);
  // The report says what to record, as a command.
  const std::string command = "`cellmetry plan " + dir + "/job.yaml --effect ur3.compliance_j2 "
                              "--effect ur3.transmission_j2` proposes";
  EXPECT_NE(DiagnosisReport(before).find(command), std::string::npos) << DiagnosisReport(before);
  EXPECT_NE(report::DiagnoseReportHtml(before, recorded, "test").find(command), std::string::npos);
  // Silent on the name, not on the site: the two tie at joint 2, and the report says both.
  const std::string tie =
      "Tied at ur3 joint 2: joint 2 compliance or joint 2 transmission error.";
  EXPECT_NE(DiagnosisReport(before).find(tie), std::string::npos) << DiagnosisReport(before);
  EXPECT_EQ(DiagnosisJson(before)["tie"].get<std::string>().rfind(tie, 0), 0u);
  EXPECT_NE(report::DiagnoseReportHtml(before, recorded, "test").find(tie), std::string::npos);
  int in_json = 0;
  const nlohmann::json json = DiagnosisJson(before);
  for (const auto& f : json["rounds"].back()["candidates"]) {
    if (f["name"] != closest->name) continue;
    EXPECT_EQ(f["rival_effect"], "ur3.transmission_j2");
    ++in_json;
  }
  EXPECT_EQ(in_json, 1);

  // The plan for the two, as the command would make it.
  PosePlanOptions options;
  options.poses = 30;
  options.effects = {closest->name, closest->rival_effect};
  const PosePlan plan = testing::Plan(job, recorded, options);
  ASSERT_EQ(plan.poses.size(), 30u);
  for (const auto& pose : plan.poses) EXPECT_FALSE(pose.cameras.empty());
  // What it predicts for the two fitted together with the geometry: every parameter better
  // determined, the compliance's sigma 2.6e-6 -> 1.8e-6 rad/(N m) (its size is 4.96e-6), the
  // transmission error's first harmonic 13 times better (joint 2's swing). How alike the poses
  // leave their signatures hardly moves (0.94 -> 0.92): a joint 2 gravity torque is nearly a
  // first harmonic of joint 2; the plan separates them by determining that harmonic.
  ASSERT_EQ(plan.pairs.size(), 1u) << PosePlanReport(plan);
  const PlannedPair& pair = plan.pairs[0];
  EXPECT_EQ(pair.a, "joint 2 compliance");
  EXPECT_EQ(pair.b, "joint 2 transmission error");
  ASSERT_EQ(pair.sigma.size(), 5u) << PosePlanReport(plan);  // compliance; h1, h2 sin and cos
  for (const PlannedSigma& s : pair.sigma) EXPECT_LT(s.after, s.before) << s.name;
  EXPECT_EQ(pair.sigma[0].name, "ur3.compliance_j2.j2.compliance");
  EXPECT_LT(pair.sigma[0].after, 0.8 * pair.sigma[0].before) << PosePlanReport(plan);
  EXPECT_LT(pair.sigma[1].after, 0.2 * pair.sigma[1].before) << PosePlanReport(plan);
  EXPECT_GT(pair.correlation_before, 0.0);
  EXPECT_LE(pair.correlation_before, 1.0);
  EXPECT_NE(PosePlanReport(plan).find("joint 2 compliance and joint 2 transmission error: alike"),
            std::string::npos)
      << PosePlanReport(plan);

  // After: the same cell and hidden compliance, the planned poses recorded after the others.
  WorkcellSimulationSpec extended = spec;
  for (const auto& pose : plan.poses) extended.robots[0].joint_poses.push_back(pose.q);
  const DiagnosisResult after =
      testing::Diagnose(job, SimulateWorkcell(extended, nullptr), dir + "/job.yaml");
  ASSERT_FALSE(after.accepted.empty()) << DiagnosisReport(after);
  EXPECT_EQ(after.accepted.front().name, "ur3.compliance_j2") << DiagnosisReport(after);
  ASSERT_EQ(after.accepted.front().parameters.size(), 1u);
  const ScalarEstimate& c = after.accepted.front().parameters[0];
  EXPECT_NEAR(c.value, kCompliance, 3 * c.sigma) << DiagnosisReport(after);
}

}  // namespace
}  // namespace cellmetry
