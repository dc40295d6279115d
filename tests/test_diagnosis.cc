// The physics finder (diagnosis.h) on simulated UR3 cells: a concealed effect is found and named
// with its joint, a clean recording gets no claim, a knocked camera is reported as unexplained,
// and recordings that cannot support the tests are refused in words.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/experiments/concealed_physics.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

class Diagnosis : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDirForThisTest("diagnosis");
    std::string sim =
        testing::ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml"));
    sim = testing::ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml",
                               testing::Source("configs/robots/ur3_vsb2020.yaml"));
    sim = testing::ReplaceOnce(sim, "random: 150", "random: 80");  // quick, still wide
    testing::WriteText(dir_ + "/sim.yaml", sim);
    base_ = LoadWorkcellSimulation(dir_ + "/sim.yaml", testing::Plugins());
    job_ = testing::Ur3DiagnoseJob(dir_);
  }

  DiagnosisResult Diagnose(const Recording& recording) {
    return testing::Diagnose(job_, recording, dir_ + "/job.yaml");
  }

  std::string dir_;
  WorkcellSimulationSpec base_;
  DiagnosisJob job_;
};

TEST_F(Diagnosis, ConcealedComplianceIsNamedWithItsJointAndModelled) {
  WorkcellSimulationSpec spec = base_;
  testing::ConcealJoint3Compliance(&spec);
  const DiagnosisResult d = Diagnose(SimulateWorkcell(spec, nullptr));
  ASSERT_FALSE(d.accepted.empty()) << DiagnosisReport(d);
  EXPECT_EQ(d.accepted.front().name, "ur3.compliance_j3") << DiagnosisReport(d);
  EXPECT_NEAR(d.accepted.front().parameters.at(0).value, 4e-5,
              3 * d.accepted.front().parameters.at(0).sigma);
  EXPECT_LT(d.final.held_out_rms_mm, 1.2 * d.floor_rms_mm);
  EXPECT_GT(d.geometric.held_out_rms_mm, d.final.held_out_rms_mm);
  // The gain is scored on the same held-out rows, so its standard error is paired: the noise
  // both models see cancels, leaving far less than the two RMS's own errors combined.
  EXPECT_TRUE(d.held_out_gain.paired);
  EXPECT_DOUBLE_EQ(d.held_out_gain.gain_mm, d.geometric.held_out_rms_mm - d.final.held_out_rms_mm);
  EXPECT_GT(d.final.held_out_rms_se_mm, 0.0);
  EXPECT_LT(d.held_out_gain.standard_error_mm,
            0.5 * std::hypot(d.geometric.held_out_rms_se_mm, d.final.held_out_rms_se_mm));
  EXPECT_THAT(DiagnosisReport(d),
              HasSubstr("Left out: joint 3 giving under gravity, best described as joint 3 "
                        "compliance under gravity"));
  // final_fit/ records how the accepted effect was built, for `cellmetry compensate`.
  ASSERT_EQ(d.final_fit.effect_models.size(), d.accepted.size());
  EXPECT_EQ(d.final_fit.effect_models.front().name, "ur3.compliance_j3");
  EXPECT_EQ(d.final_fit.effect_models.front().stage, "joint");
  EXPECT_THAT(d.final_fit.effect_models.front().config,
              HasSubstr("{type: joint_compliance, joints: [3], link_masses_kg: [2"));
}

// A joint 3 "compliance" that bends the joint against gravity has a compliance's signature but
// no physics: the finder refits it and never names it (Parameter::plausible_nonnegative); its
// refit says why (diagnosis.json).
TEST_F(Diagnosis, AComplianceBelowZeroIsNeverNamed) {
  WorkcellSimulationSpec spec = base_;
  testing::ConcealJoint3Compliance(&spec, -4e-5);
  const DiagnosisResult d = Diagnose(SimulateWorkcell(spec, nullptr));
  for (const auto& accepted : d.accepted) {
    EXPECT_NE(accepted.name, "ur3.compliance_j3") << DiagnosisReport(d);
  }
  ASSERT_FALSE(d.rounds.empty());
  const auto& candidates = d.rounds.front().candidates;
  const auto compliance = std::find_if(candidates.begin(), candidates.end(),
                                       [](const auto& c) { return c.name == "ur3.compliance_j3"; });
  ASSERT_NE(compliance, candidates.end());
  ASSERT_TRUE(compliance->refitted) << DiagnosisReport(d);
  EXPECT_THAT(compliance->implausible, HasSubstr("below zero, which this physics cannot be"));
}

TEST_F(Diagnosis, CleanRecordingGetsNoClaim) {
  const DiagnosisResult d = Diagnose(SimulateWorkcell(base_, nullptr));
  EXPECT_TRUE(d.accepted.empty()) << DiagnosisReport(d);
  EXPECT_TRUE(d.geometric.consistent_with_noise());
  // Joint 1 turns about the vertical: its compliance cannot act, and the report says so.
  EXPECT_THAT(DiagnosisReport(d), HasSubstr("joint 1 compliance (it does not act"));
  // The best candidate was tried and refused, and the report says on which test.
  EXPECT_THAT(DiagnosisReport(d), HasSubstr("not accepted:"));
}

TEST_F(Diagnosis, KnockedCameraIsUnexplainedNotForcedIntoAName) {
  WorkcellSimulationSpec spec = base_;
  ConcealedPhysics bump;
  bump.kind = "camera_bump";
  bump.camera = "cam1";
  bump.magnitude = 0.15;  // mm, from the middle of the run on
  spec.concealed.push_back(std::make_shared<ConcealedPhysics>(bump));
  const DiagnosisResult d = Diagnose(SimulateWorkcell(spec, nullptr));
  EXPECT_TRUE(d.accepted.empty()) << DiagnosisReport(d);
  EXPECT_THAT(d.unexplained, HasSubstr("in cam1")) << DiagnosisReport(d);
  EXPECT_THAT(d.unexplained, HasSubstr("a step after capture")) << DiagnosisReport(d);
}

// A hidden effect of `type` (`yaml`) on the UR3 cell, at `values`.
WorkcellSimulationSpec WithHidden(WorkcellSimulationSpec spec, const std::string& yaml,
                                  std::vector<double> values) {
  const ConfigNode config = ConfigNode::LoadString(yaml, "test");
  SimulatedEffect e;
  e.name = "hidden";
  e.effect =
      testing::Plugins().CreateEffect(config["type"].AsString(), config, *spec.robots[0].model);
  e.values = std::move(values);
  const bool measurement = e.effect->stage() == EffectStage::kMeasurement;
  (measurement ? spec.measurement_effects : spec.robots[0].effects).push_back(e);
  return spec;
}

TEST_F(Diagnosis, PrintedBoardSizeIsNamedAsTheTarget) {
  const WorkcellSimulationSpec spec =
      WithHidden(base_, "{type: target_scale, targets: [tool]}", {0.004});
  const DiagnosisResult d = Diagnose(SimulateWorkcell(spec, nullptr));
  ASSERT_FALSE(d.accepted.empty()) << DiagnosisReport(d);
  EXPECT_EQ(d.accepted.front().name, "target.scale_tool") << DiagnosisReport(d);
  EXPECT_NEAR(d.accepted.front().parameters.at(0).value, 0.004,
              3 * d.accepted.front().parameters.at(0).sigma);
}

// A wrist whose joint 6 turns with joint 5 (its shaft runs through joint 5, and the controller's
// coupling ratio is off by 3 mrad/rad): named as that coupling, among the wrist's three, once the
// job says the drives couple them.
TEST_F(Diagnosis, WristCouplingTheJobNamesIsFound) {
  job_.options.joint_couplings = {{4, 5}, {4, 6}, {5, 6}};
  const WorkcellSimulationSpec spec =
      WithHidden(base_, "{type: joint_coupling, joints: [6], from: 5}", {3e-3});
  const DiagnosisResult d = Diagnose(SimulateWorkcell(spec, nullptr));
  ASSERT_FALSE(d.accepted.empty()) << DiagnosisReport(d);
  EXPECT_EQ(d.accepted.front().name, "ur3.coupling_j6_j5") << DiagnosisReport(d);
  EXPECT_EQ(d.accepted.front().site, "ur3 joint 6");
  EXPECT_NEAR(d.accepted.front().parameters.at(0).value, 3e-3,
              3 * d.accepted.front().parameters.at(0).sigma);
  EXPECT_THAT(DiagnosisReport(d), HasSubstr("joint 6 coupled to joint 5"));
}

// Couplings are pairs of two different joints the cell's robots have, offered among the default
// candidates; anything else, or couplings beside a job's own list, is refused at its line.
TEST_F(Diagnosis, JointCouplingsTheRobotCannotHaveAreRefusedAtTheirLine) {
  const std::string job = testing::ReadText(dir_ + "/job.yaml");
  for (const auto& [couplings, words] : std::vector<std::pair<std::string, std::string>>{
           {"[[5, 5]]", "does not couple to itself"},
           {"[[5, 7]]", "no joint 7 on the cell's robots"},
           {"[[4, 5, 6]]", "a coupling is two joints"},
           {"[[5, 6]]\n  candidates: [{type: backlash, joints: [2]}]",
            "shapes the default candidates, which `candidates:` replaces"}}) {
    testing::WriteText(dir_ + "/bad.yaml", job + "  joint_couplings: " + couplings + "\n");
    const InputError e = testing::CatchInputError(
        [&] { LoadDiagnosisJob(dir_ + "/bad.yaml", testing::Plugins(), false); });
    EXPECT_THAT(e.message(), HasSubstr(words)) << couplings;
    EXPECT_THAT(e.what(), HasSubstr("bad.yaml:")) << couplings;
  }
}

// A joint 3 transmission error ten times what a harmonic drive has: the finder may see its
// signature but must not name a transmission error of that size (the 2020 recording's 22 mrad).
TEST_F(Diagnosis, ImplausibleSizeIsNeverReportedAsThatPhysics) {
  const WorkcellSimulationSpec spec =
      WithHidden(base_, "{type: transmission_error, joints: [3], harmonics: [1]}", {0.02, 0.0});
  const DiagnosisResult d = Diagnose(SimulateWorkcell(spec, nullptr));
  for (const auto& a : d.accepted) {
    EXPECT_EQ(a.name.find("transmission_j3"), std::string::npos) << DiagnosisReport(d);
  }
  bool ruled_out = false;
  for (const auto& round : d.rounds) {
    for (const auto& f : round.candidates) {
      if (f.accepted) {
        EXPECT_TRUE(f.implausible.empty()) << f.label << ": " << f.implausible;
      }
      ruled_out |= f.name.find("transmission_j3") != std::string::npos && !f.implausible.empty();
    }
  }
  EXPECT_TRUE(ruled_out) << DiagnosisReport(d);
  if (d.accepted.empty()) {
    EXPECT_THAT(DiagnosisReport(d), HasSubstr("its fitted size rules it out"));
  }
}

TEST_F(Diagnosis, TooFewPosesIsRefusedInWords) {
  WorkcellSimulationSpec spec = base_;
  spec.robots[0].joint_poses.resize(12);
  const InputError e = testing::CatchInputError([&] { Diagnose(SimulateWorkcell(spec, nullptr)); });
  EXPECT_THAT(e.message(), HasSubstr("too few samples for the tests: 12 poses"));
  EXPECT_THAT(e.hint(), HasSubstr("Record more poses"));
}

TEST_F(Diagnosis, NoRepeatsAndNoSigmaIsRefusedInWords) {
  job_.workcell.problem.noise = NoiseSpec{};
  const InputError e =
      testing::CatchInputError([&] { Diagnose(SimulateWorkcell(base_, nullptr)); });
  EXPECT_THAT(e.message(), HasSubstr("no repeated captures and no sigma given"));
  EXPECT_THAT(e.hint(), HasSubstr("two or more times"));
}

TEST_F(Diagnosis, RegressorColumnWithNanIsRefusedWithFileAndLine) {
  WorkcellTruth truth;
  WriteRecording(SimulateWorkcell(base_, &truth), dir_ + "/rec");
  const std::string samples = testing::ReadText(dir_ + "/rec/samples.csv");
  std::string line5 = samples;
  for (int i = 0; i < 4; ++i) line5 = line5.substr(line5.find('\n') + 1);
  line5 = line5.substr(0, line5.find('\n'));
  // samples.csv ends with t,temperature,payload: the payload of line 5 becomes NaN.
  ASSERT_THAT(samples.substr(0, samples.find('\n')), ::testing::EndsWith(",payload"));
  testing::EditLine(dir_ + "/rec/samples.csv", 5, line5.substr(0, line5.rfind(',')) + ",nan");
  const InputError e = testing::CatchInputError([&] { ReadRecording(dir_ + "/rec"); });
  EXPECT_THAT(e.what(), HasSubstr("samples.csv:5"));
  EXPECT_THAT(e.message(), HasSubstr("payload"));
}

// The delta cell (configs/simulations/delta_physics_base.yaml), 80 poses, with one hidden effect.
class DeltaDiagnosis : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDirForThisTest("delta_diagnosis");
    const std::string delta = testing::Source("configs/robots/delta.yaml");
    std::string sim =
        testing::ReadText(testing::Source("configs/simulations/delta_physics_base.yaml"));
    sim = testing::ReplaceOnce(sim, "../robots/delta.yaml", delta);
    sim = testing::ReplaceOnce(sim, "random: 150", "random: 80");
    testing::WriteText(dir_ + "/sim.yaml", sim);
    spec_ = LoadWorkcellSimulation(dir_ + "/sim.yaml", testing::Plugins());
    std::string job = testing::ReadText(testing::Source("configs/jobs/delta_diagnose.yaml"));
    job = testing::ReplaceOnce(job, "model: ../robots/delta.yaml", "model: " + delta);
    testing::WriteText(dir_ + "/job.yaml", job);
    job_ = LoadDiagnosisJob(dir_ + "/job.yaml", testing::Plugins(), false);
    job_.options.bootstrap = 30;
  }

  DiagnosisResult DiagnoseWith(const std::string& yaml, double value) {
    SimulatedEffect e;
    const ConfigNode config = ConfigNode::LoadString(yaml, "test");
    e.name = "delta.hidden";
    e.effect =
        testing::Plugins().CreateEffect(config["type"].AsString(), config, *spec_.robots[0].model);
    e.values = {value};
    spec_.robots[0].effects.push_back(e);
    return testing::Diagnose(job_, SimulateWorkcell(spec_, nullptr), dir_ + "/job.yaml");
  }

  std::string dir_;
  WorkcellSimulationSpec spec_;
  DiagnosisJob job_;
};

// A parallelogram out of true is found and named with its arm, with the delta's geometry
// calibrated alongside.
TEST_F(DeltaDiagnosis, SkewedParallelogramIsNamedWithItsArm) {
  const DiagnosisResult d = DiagnoseWith("{type: platform_tilt, arms: [1]}", 2e-3);  // rad
  ASSERT_FALSE(d.accepted.empty()) << DiagnosisReport(d);
  EXPECT_EQ(d.accepted.front().name, "delta.tilt_arm1") << DiagnosisReport(d);
  EXPECT_NEAR(d.accepted.front().parameters.at(0).value, 2e-3,
              3 * d.accepted.front().parameters.at(0).sigma);
  EXPECT_LT(d.final.held_out_rms_mm, 1.2 * d.floor_rms_mm);
}

// A delta's motors do not carry each other; a motor gives under the load the flange puts on it
// (platform and payload through the Jacobian), which changes with the payload from pose to pose.
// At 4e-4 rad/(N m), inside the compliance's plausible range (a drive stiffer than 2,000 N m/rad);
// softer, the finder would rule it out by its size.
TEST_F(DeltaDiagnosis, MotorComplianceUnderTheFlangeLoadIsNamed) {
  const DiagnosisResult d =
      DiagnoseWith("{type: joint_compliance, joints: [2], link_masses_kg: [0.1, 0.1, 0.1]}", 4e-4);
  ASSERT_FALSE(d.accepted.empty()) << DiagnosisReport(d);
  EXPECT_EQ(d.accepted.front().name, "delta.compliance_j2") << DiagnosisReport(d);
  EXPECT_NEAR(d.accepted.front().parameters.at(0).value, 4e-4,
              3 * d.accepted.front().parameters.at(0).sigma);
}

// Motor 1 swings 2 rad, less than a turn: its gear ratio error and its once-per-turn
// transmission error are one signature here. The finding is made, and both names are given.
TEST_F(DeltaDiagnosis, GearRatioOverLessThanATurnIsNamedWithItsAlias) {
  const DiagnosisResult d = DiagnoseWith("{type: joint_scale, joints: [1]}", 4e-3);
  ASSERT_FALSE(d.accepted.empty()) << DiagnosisReport(d);
  const AcceptedEffect& a = d.accepted.front();
  const bool scale = a.name == "delta.scale_j1";
  EXPECT_TRUE(scale || a.name.rfind("delta.transmission_j1", 0) == 0) << DiagnosisReport(d);
  ASSERT_FALSE(a.aliases.empty()) << DiagnosisReport(d);
  EXPECT_THAT(DiagnosisReport(d), HasSubstr("indistinguishable from joint 1"));
}

}  // namespace
}  // namespace cellmetry
