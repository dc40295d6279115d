// The physics finder's proof harness (physics_suite.h): its tables go into docs/physics.md
// between markers, an interrupted suite resumes from its checkpoint without rerunning finished
// cases, and a bad suite file is refused with its line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cellmetry/experiments/physics_suite.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

std::string SuiteYaml(const std::string& seeds) {
  return "compare: physics\nseeds: " + seeds +
         "\nsnr: 6\ncells:\n  - name: delta\n"
         "    simulation: " +
         testing::Source("configs/simulations/delta_physics_base.yaml") +
         "\n    job: " + testing::Source("configs/jobs/delta_diagnose.yaml") +
         "\n    cases:\n      - {name: clean, expect: none}\n"
         "      - {name: arm 1 skew, expect: delta.tilt_arm1, effect: {type: platform_tilt, arms: "
         "[1]}}\n"
         "output: doc.md\n";
}

TEST(PhysicsSuite, TablesGoBetweenTheMarkersAndTheRestStays) {
  const std::string dir = testing::TempDirForThisTest("suite");
  testing::WriteText(dir + "/suite.yaml", SuiteYaml("1"));
  const PhysicsSuiteSpec spec = LoadPhysicsSuite(dir + "/suite.yaml");
  testing::WriteText(dir + "/doc.md",
                     "# Before\n<!-- physics-suite:begin -->\nold table\n"
                     "<!-- physics-suite:end -->\n## After\n");
  WritePhysicsSuite(spec, dir + "/doc.md", "new table\n");
  EXPECT_EQ(testing::ReadText(dir + "/doc.md"),
            "# Before\n<!-- physics-suite:begin -->\nnew table\n<!-- physics-suite:end -->\n"
            "## After\n");
  // A new file holds the markers, so that the next run replaces only the tables.
  WritePhysicsSuite(spec, dir + "/new.md", "first table\n");
  EXPECT_EQ(testing::ReadText(dir + "/new.md"),
            "<!-- physics-suite:begin -->\nfirst table\n<!-- physics-suite:end -->\n");
  testing::WriteText(dir + "/new.md", testing::ReadText(dir + "/new.md") + "a note\n");
  WritePhysicsSuite(spec, dir + "/new.md", "second table\n");
  EXPECT_EQ(testing::ReadText(dir + "/new.md"),
            "<!-- physics-suite:begin -->\nsecond table\n<!-- physics-suite:end -->\na note\n");
}

// A document without the markers (a user's README named as the output) is refused, before the
// suite runs and again at the write, and kept as it was.
TEST(PhysicsSuite, ADocumentWithoutTheMarkersIsRefusedAndKept) {
  const std::string dir = testing::TempDirForThisTest("suite");
  testing::WriteText(dir + "/suite.yaml", SuiteYaml("1"));
  const PhysicsSuiteSpec spec = LoadPhysicsSuite(dir + "/suite.yaml");
  const std::string readme =
      "# My notes\n<!-- physics-suite:end -->\n<!-- physics-suite:begin -->\n";
  testing::WriteText(dir + "/README.md", readme);
  const InputError e =
      testing::CatchInputError([&] { CheckPhysicsSuiteOutput(dir + "/README.md"); });
  EXPECT_THAT(e.what(), HasSubstr("README.md"));
  EXPECT_THAT(e.message(), HasSubstr("has no <!-- physics-suite:begin -->"));
  EXPECT_THAT(e.hint(), HasSubstr("Put the two markers"));
  EXPECT_THROW(WritePhysicsSuite(spec, dir + "/README.md", "table\n"), InputError);
  EXPECT_THROW(CheckPhysicsSuiteOutput(dir), InputError);  // a folder
  EXPECT_EQ(testing::ReadText(dir + "/README.md"), readme);
  EXPECT_NO_THROW(CheckPhysicsSuiteOutput(dir + "/not_yet.md"));
}

// A suite's checkpoint (SuiteYaml(seeds)) with each case's first seed finished: the clean case
// named nothing in 2.0 s, the skewed arm its tilt in 2.5 s.
void WriteFirstSeedsFinished(const std::string& path, const std::string& seeds) {
  auto run = [](const std::string& named, double held_out_over_floor, double seconds) {
    return nlohmann::json::array({{{"named", named},
                                   {"failed", ""},
                                   {"held_out_over_floor", held_out_over_floor},
                                   {"seconds", seconds}}});
  };
  const std::string at = "/" + seeds + "/6.000";
  nlohmann::json checkpoint;
  checkpoint["delta/clean" + at] = {{"magnitude", 0.0}, {"runs", run("none", 0.97, 2.0)}};
  checkpoint["delta/arm 1 skew" + at] = {{"magnitude", 5e-4},
                                         {"runs", run("delta.tilt_arm1", 0.99, 2.5)}};
  testing::WriteText(path, checkpoint.dump());
}

// Both cases finished before the interruption: the resumed suite reads them back and diagnoses
// nothing (it would take seconds per run otherwise), then the checkpoint goes with the write.
TEST(PhysicsSuite, InterruptedSuiteResumesFromItsCheckpoint) {
  const std::string dir = testing::TempDirForThisTest("suite_resume");
  testing::WriteText(dir + "/suite.yaml", SuiteYaml("1"));
  const PhysicsSuiteSpec spec = LoadPhysicsSuite(dir + "/suite.yaml");
  WriteFirstSeedsFinished(dir + "/doc.md.partial.json", "1");
  const auto results = RunPhysicsSuite(spec, testing::Plugins());
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[1].runs.at(0).named, "delta.tilt_arm1");
  EXPECT_EQ(results[1].right(), 1);
  EXPECT_DOUBLE_EQ(results[1].magnitude, 5e-4);
  EXPECT_DOUBLE_EQ(results[1].runs.at(0).seconds, 2.5);  // read back, not rerun
  const std::string table = PhysicsSuiteMarkdown(spec, results);
  EXPECT_THAT(table, HasSubstr("| right effect named (library and richer variants) | "
                               "100 % [21 %, 100 %] (1/1) | >= 90 % | undecided |"));
  EXPECT_THAT(table, HasSubstr("| outside the library reported as unexplained | - | all | - |"));
  WritePhysicsSuite(spec, dir + "/doc.md", table);
  EXPECT_FALSE(std::filesystem::exists(dir + "/doc.md.partial.json"));
}

// Stopped after the first seed of every case (the suite runs seed by seed over the cases, so
// that its rate after the first tenth holds for the rest): the resumed suite reads each case's
// first seed back and runs only the second.
TEST(PhysicsSuite, InterruptedSuiteResumesWithinACaseAtTheSeedItReached) {
  const std::string dir = testing::TempDirForThisTest("suite_resume_seeds");
  testing::WriteText(dir + "/suite.yaml", SuiteYaml("2"));
  const PhysicsSuiteSpec spec = LoadPhysicsSuite(dir + "/suite.yaml");
  WriteFirstSeedsFinished(dir + "/doc.md.partial.json", "2");
  const auto results = RunPhysicsSuite(spec, testing::Plugins());
  ASSERT_EQ(results.size(), 2u);
  for (const auto& result : results) ASSERT_EQ(result.runs.size(), 2u) << result.spec.name;
  EXPECT_DOUBLE_EQ(results[0].runs[0].seconds, 2.0);  // read back
  EXPECT_DOUBLE_EQ(results[1].runs[0].seconds, 2.5);
  EXPECT_DOUBLE_EQ(results[1].magnitude, 5e-4);  // the second seed ran at the kept size
  EXPECT_NE(results[1].runs[1].seconds, 2.5);    // run, not copied
}

// A case's runs are its seeds: each must draw its own noise, or five runs are one run counted
// five times (the merged simulator once read the noise seed from elsewhere, and every case came
// out 5/5 or 0/5).
TEST(PhysicsSuite, EachSeedDrawsItsOwnNoise) {
  const std::string dir = testing::TempDirForThisTest("suite_seeds");
  testing::WriteText(dir + "/suite.yaml",
                     "compare: physics\nseeds: 2\nsnr: 6\ncells:\n  - name: delta\n"
                     "    simulation: " +
                         testing::Source("configs/simulations/delta_physics_base.yaml") +
                         "\n    job: " + testing::Source("configs/jobs/delta_diagnose.yaml") +
                         "\n    cases:\n      - {name: clean, expect: none}\noutput: doc.md\n");
  const auto results = RunPhysicsSuite(LoadPhysicsSuite(dir + "/suite.yaml"), testing::Plugins());
  ASSERT_EQ(results.size(), 1u);
  ASSERT_EQ(results[0].runs.size(), 2u);
  EXPECT_NE(results[0].runs[0].held_out_over_floor, results[0].runs[1].held_out_over_floor);
}

// The oracle beside each case: the oracle reads the case's mismatch at the suite's SNR (the
// same noise-free recording and fit that set its size), names a skewed parallelogram, which no
// other candidate resembles, nearly always, makes no draws for a clean recording or for a case no
// candidate names, and the tables carry it.
TEST(PhysicsSuite, EachEffectCaseCarriesTheOraclesBestGuess) {
  const std::string dir = testing::TempDirForThisTest("suite_oracle");
  std::string yaml = SuiteYaml("1");
  const std::string last_case = "[1]}}\n";
  yaml.insert(yaml.find(last_case) + last_case.size(),
              "      - {name: skew named otherwise, expect: delta.no_such_effect, "
              "effect: {type: platform_tilt, arms: [1]}}\n");
  testing::WriteText(dir + "/suite.yaml", yaml);
  const PhysicsSuiteSpec spec = LoadPhysicsSuite(dir + "/suite.yaml");
  const auto results = RunPhysicsSuite(spec, testing::Plugins());
  ASSERT_EQ(results.size(), 3u);
  EXPECT_EQ(results[0].oracle.draws(), 0);  // clean
  const OracleSelection& skew = results[1].oracle;
  EXPECT_EQ(skew.draws(), OracleSelectionOptions{}.draws);
  EXPECT_NEAR(skew.mismatch_norm, spec.snr, 0.05 * spec.snr);
  EXPECT_GE(skew.right_share(), 0.95);
  EXPECT_GT(skew.testable, 10);
  EXPECT_EQ(results[2].oracle.draws(), 0);
  EXPECT_EQ(results[2].oracle.right_candidates, 0);
  const std::string table = PhysicsSuiteMarkdown(spec, results);
  EXPECT_THAT(table, HasSubstr("| the oracle's best guess on each case's poses"));
  EXPECT_THAT(table, HasSubstr("| delta | arm 1 skew | delta.tilt_arm1 |"));
  EXPECT_THAT(table, HasSubstr(" % wrong, over 1 cases |"));
}

TEST(PhysicsSuite, NoRunsPerCaseIsRefusedWithItsLine) {
  const std::string dir = testing::TempDirForThisTest("suite_bad");
  testing::WriteText(dir + "/suite.yaml", SuiteYaml("0"));
  const InputError e = testing::CatchInputError([&] { LoadPhysicsSuite(dir + "/suite.yaml"); });
  EXPECT_THAT(e.what(), HasSubstr("suite.yaml:2"));
  EXPECT_THAT(e.message(), HasSubstr("at least 1 run per case"));
}

// What counts as right: the expected name or a nested variant of it, an exact alias, or (where
// the case expects one) the group of the named form; silence and other names do not count.
TEST(PhysicsSuite, ARunIsRightByNameAliasOrExpectedGroup) {
  SuiteCaseResult lens;
  lens.spec.expect = "camera.calibration_cam2";
  SuiteRun tilt{"camera.depth_tilt_cam2", "", 1.0, 0.1, {}, "camera.calibration_cam2"};
  EXPECT_TRUE(lens.named_right(tilt));
  tilt.group = "camera.calibration_cam1";  // the other camera's calibration
  EXPECT_FALSE(lens.named_right(tilt));
  EXPECT_FALSE(lens.named_right({"none", "bootstrap", 1.0, 0.1, {}, ""}));

  SuiteCaseResult gear;
  gear.spec.expect = "ur3.transmission_j4";
  EXPECT_TRUE(gear.named_right({"ur3.transmission_j4_h1", "", 1.0, 0.1, {}, ""}));
  SuiteCaseResult focal;
  focal.spec.expect = "camera.focal_cam2";
  // A form's case wants the form: its group alone is not enough.
  EXPECT_FALSE(
      focal.named_right({"camera.radial_cam2", "", 1.0, 0.1, {}, "camera.calibration_cam2"}));
  EXPECT_TRUE(focal.named_right(
      {"camera.depth_cam2", "", 1.0, 0.1, {"camera.focal_cam2"}, "camera.calibration_cam2"}));
}

}  // namespace
}  // namespace cellmetry
