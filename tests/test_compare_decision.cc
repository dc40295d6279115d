// `compare: solvers`: the 95 % t-interval, the decision (a tie, a clear winner, the
// same accuracy at less time) on small synthetic inputs, and one comparison end to end.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "cellmetry/experiments/intervals.h"
#include "cellmetry/experiments/kinematic_compare.h"
#include "cellmetry/experiments/marker_comparison.h"
#include "cellmetry/experiments/physics_suite.h"
#include "cellmetry/experiments/solver_compare.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(TInterval95, IsTheStudentInterval) {
  const MeanInterval m = TInterval95({1.0, 2.0, 3.0});  // s = 1, t(0.975, 2) = 4.302653
  EXPECT_DOUBLE_EQ(m.mean, 2.0);
  EXPECT_NEAR(m.high - m.mean, 4.302653 / std::sqrt(3.0), 1e-6);
  EXPECT_NEAR(m.mean - m.low, 4.302653 / std::sqrt(3.0), 1e-6);
  const MeanInterval one = TInterval95({5.0});  // one value: nothing can be told apart
  EXPECT_TRUE(std::isinf(one.low) && std::isinf(one.high));
}

// Wilson's interval (1927) against values worked by hand: 5 of 5 is [n/(n+z^2), 1], not 100 %.
TEST(WilsonInterval95, MatchesTheScoreIntervalAndNeverLeavesZeroOne) {
  const RateInterval all = WilsonInterval95(5, 5);
  EXPECT_NEAR(all.low, 5.0 / (5.0 + 1.959964 * 1.959964), 1e-6);
  EXPECT_DOUBLE_EQ(all.high, 1.0);
  const RateInterval none = WilsonInterval95(0, 10);
  EXPECT_DOUBLE_EQ(none.low, 0.0);
  EXPECT_NEAR(none.high, 3.841459 / (10 + 3.841459), 1e-6);
  const RateInterval half = WilsonInterval95(50, 100);  // symmetric about 1/2
  EXPECT_NEAR(half.low + half.high, 1.0, 1e-12);
  EXPECT_NEAR(half.high - half.low, 2 * 0.0961, 2e-4);  // z sqrt(pq/n) / (1 + z^2/n) ~ 0.0961
  EXPECT_EQ(RunsToShowAtLeast(0.90), 35);
  EXPECT_EQ(RunsToShowAtLeast(0.95), 73);
  EXPECT_EQ(AgainstTarget(WilsonInterval95(35, 35), 0.90), TargetVerdict::kMet);
  EXPECT_EQ(AgainstTarget(WilsonInterval95(34, 34), 0.90), TargetVerdict::kUndecided);
  EXPECT_EQ(AgainstTarget(WilsonInterval95(3, 5), 0.90), TargetVerdict::kMissed);
  // 87 % against 90 %: undecided at 125 runs, decided by the runs RunsToDecide names.
  const int runs = RunsToDecide(0.872, 0.90, 125);
  ASSERT_GT(runs, 125);
  EXPECT_EQ(AgainstTarget(WilsonInterval95(static_cast<int>(0.872 * runs), runs), 0.90),
            TargetVerdict::kMissed);
  EXPECT_EQ(RunsToDecide(0.90, 0.90, 100), -1);  // at the target: no number of runs decides
}

// The three ways a comparison's table writes a figure, and an interval in each.
TEST(FigureText, WritesEachStyleAsItsTableDoes) {
  EXPECT_EQ(FigureText(12.3456), "12.3");
  EXPECT_EQ(FigureText(0.000123), "1.23e-04");
  EXPECT_EQ(FigureText(0.0), "0");
  EXPECT_EQ(FigureText(12.3456, FigureStyle::kFourDecimals), "12.3456");
  EXPECT_EQ(FigureText(0.000123, FigureStyle::kFourDecimals), "1.2e-04");
  EXPECT_EQ(FigureText(12.3456, FigureStyle::kFourDigits), "12.35");
  EXPECT_EQ(FigureText(INFINITY), "inf");
  const MeanInterval m{2.0, 1.5, 2.5, 3};
  EXPECT_EQ(IntervalText(m), "2 [1.5, 2.5]");
  EXPECT_EQ(IntervalText(m, 1e3), "2e+03 [1.5e+03, 2.5e+03]");
  EXPECT_EQ(IntervalText(m, 1.0, FigureStyle::kFourDecimals), "2.0000 [1.5000, 2.5000]");
  EXPECT_EQ(IntervalText(std::vector<double>{}), "-");
}

// The physics suite's decisions: a case named 2 of 5 times is shown below 90 % with what was
// named instead; 5 of 5 is undecided, not met; a wrong claim on a clean recording is counted.
TEST(PhysicsSuiteRecommendations, SayMetMissedOrUndecidedWithWhatWouldDecide) {
  PhysicsSuiteSpec spec;
  spec.snr = 6.0;
  spec.cells.push_back({"UR3", "", "", {}});
  auto result = [](const std::string& name, const std::string& expect,
                   const std::vector<std::string>& named) {
    SuiteCaseResult r;
    r.cell = "UR3";
    r.spec.name = name;
    r.spec.expect = expect;
    for (const auto& n : named) r.runs.push_back({n, "", 1.0, 1.0, {}, ""});
    return r;
  };
  std::vector<SuiteCaseResult> results = {
      result("clean", "none", {"none", "none", "none", "none", "ur3.thermal"}),
      result("joint 3 backlash", "ur3.backlash_j3", std::vector<std::string>(5, "ur3.backlash_j3")),
      result("joint 2 compliance", "ur3.compliance_j2",
             {"ur3.compliance_j2", "none", "ur3.scale_j2", "none", "ur3.compliance_j2"}),
      result("cam bumped", "unexplained", {"unexplained", "unexplained", "unexplained"}),
      result("richer: warm-up", "ur3.thermal", {"ur3.thermal", "ur3.thermal", "none"})};
  std::vector<SuiteCaseResult> library_only(results.begin(), results.end() - 1);
  results.back().spec.concealed = ConfigNode::LoadString("{kind: warmup}", "test");
  std::vector<std::string> lines = PhysicsSuiteRecommendations(spec, library_only);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_THAT(lines[0], HasSubstr("Is the right effect named? missed: 70 % [40 %, 89 %] (7/10)"));
  EXPECT_THAT(lines[1], HasSubstr("Are the richer variants named? not asked (no such cases)"));
  EXPECT_THAT(lines[2], HasSubstr("Do clean recordings stay clean? undecided: 80 % [38 %, 96 %]"));
  EXPECT_THAT(lines[2], HasSubstr("runs would decide it (5 so far)"));
  EXPECT_THAT(lines[3], HasSubstr("so far: 100 % [44 %, 100 %] (3/3), no miss"));
  EXPECT_THAT(lines[4], HasSubstr("held-out RMS to the floor? met: 1.00 [1.00, 1.00]"));
  EXPECT_THAT(lines[5], HasSubstr("UR3 at SNR 6.0: shown below 90 %"));
  EXPECT_THAT(lines[5],
              HasSubstr("joint 2 compliance 2/5 (named instead: none 2, ur3.scale_j2 1)"));
  EXPECT_THAT(lines[5], HasSubstr("0 shown at or above, 1 undecided"));
  // A richer variant (concealed physics) counts in both rates, and alone in its own.
  lines = PhysicsSuiteRecommendations(spec, results);
  EXPECT_THAT(lines[0], HasSubstr("Is the right effect named? missed: 69 % [42 %, 87 %] (9/13)"));
  EXPECT_THAT(lines[1], HasSubstr("Are the richer variants named? undecided: 67 % [21 %, 94 %]"));
  EXPECT_THAT(PhysicsSuiteMarkdown(spec, results),
              HasSubstr("| of them, richer variants (physics not in the library's equations): "
                        "named; wrong | 67 % [21 %, 94 %] (2/3); 0/3 |"));
  EXPECT_THAT(PhysicsSuiteMarkdown(spec, results), HasSubstr("Decisions:"));
}

// Two solvers whose per-seed errors and times differ by noise alone: a tie.
TEST(Recommendation, CallsATieATie) {
  const std::vector<Contender> c = {
      {"a", {1.00, 1.10, 0.90, 1.05, 0.95}, {0.010, 0.011, 0.009, 0.010, 0.012}},
      {"b", {1.04, 1.02, 0.97, 1.08, 0.91}, {0.011, 0.010, 0.010, 0.012, 0.009}}};
  const std::string line = Recommendation("q", c, "mm");
  EXPECT_THAT(line, HasSubstr("q: tie: "));
  EXPECT_THAT(line, HasSubstr("a"));
  EXPECT_THAT(line, HasSubstr("b"));
  EXPECT_THAT(line, Not(HasSubstr("more accurate")));
}

TEST(Recommendation, NamesAClearlyMoreAccurateOne) {
  const std::vector<Contender> c = {
      {"slow_good", {1.00, 1.10, 0.90, 1.05, 0.95}, {0.04, 0.04, 0.04, 0.04, 0.04}},
      {"fast_bad", {2.00, 2.10, 1.90, 2.05, 1.95}, {0.01, 0.01, 0.01, 0.01, 0.01}},
      {"worst", {3.00, 3.10, 2.90, 3.05, 2.95}, {0.01, 0.01, 0.01, 0.01, 0.01}}};
  const std::string line = Recommendation("q", c, "mm");
  EXPECT_THAT(line, HasSubstr("q: slow_good: more accurate than fast_bad (1 ["));
  EXPECT_THAT(line, HasSubstr("at 4x its time"));
  EXPECT_THAT(line, HasSubstr("less accurate: worst"));
}

TEST(Recommendation, SameAccuracyAtLessTime) {
  const std::vector<Contender> c = {
      {"nlopt", {1.00, 1.10, 0.90, 1.05, 0.95}, {0.040, 0.042, 0.039, 0.041, 0.040}},
      {"ceres_lm", {1.00, 1.10, 0.90, 1.05, 0.95}, {0.010, 0.011, 0.010, 0.010, 0.009}}};
  EXPECT_THAT(Recommendation("for this cell", c, "mm"),
              HasSubstr("for this cell: ceres_lm: same accuracy as nlopt at 1/4 the time"));
}

// Unpaired (different seed counts): overlapping intervals are the same.
TEST(Recommendation, UnpairedScoresCompareByOverlap) {
  EXPECT_TRUE(SameScore({1.0, 1.2, 0.8}, {1.1, 0.9, 1.3, 1.0}));
  EXPECT_FALSE(SameScore({1.0, 1.01, 0.99}, {2.0, 2.01, 1.99, 2.02}));
  // Paired: a small difference that every seed shows is a difference.
  EXPECT_FALSE(SameScore({1.00, 1.50, 0.70, 1.20}, {1.05, 1.56, 0.74, 1.26}));
}

TEST(StopReasonWords, CountsReasonsNotTheirPerRunFigures) {
  EXPECT_EQ(StopReasonWords("Parameter tolerance reached. Relative step_norm: 5.798454e-13 <= "
                            "1.000000e-12."),
            "Parameter tolerance reached");
  EXPECT_EQ(StopReasonWords("5000 epochs done (limit); kept epoch 4994, the lowest cost"),
            "5000 epochs done (limit)");
  EXPECT_EQ(StopReasonWords("predicted cost decrease 2.2e-12 below the tolerance"),
            "predicted cost decrease below the tolerance");
}

// Round-off of a noise-free fit (1e-13 mm) is no difference, however consistent.
TEST(Recommendation, DifferencesBelowTheResolutionAreTies) {
  const std::vector<Contender> c = {{"lm", {5.1e-13, 5.3e-13, 5.2e-13}, {0.001, 0.001, 0.001}},
                                    {"pinv", {2.1e-13, 2.3e-13, 2.2e-13}, {0.001, 0.001, 0.001}}};
  EXPECT_THAT(Recommendation("q", c, "mm"), HasSubstr("q: tie: "));
}

// Table 7 with seeds: every row repeated; seed 0 is the one-seed table's row, unchanged.
TEST(KinematicCompare, SeedsRepeatEveryRowAndKeepSeedZero) {
  const std::string dir = testing::TempDirForThisTest("compare_solvers");
  const std::string text =
      "compare: kinematic\n"
      "simulation: " +
      testing::Source("configs/compare/delta_table7_simulation.yaml") +
      "\n"
      "pose_sets: [uniform_workspace]\nsizes: [24]\nformulations: [forward]\n"
      "solvers: {lm: {type: ceres_lm}, pinv: {type: jacobian_pinv}}\n"
      "validation_points: 20\n";
  testing::WriteText(dir + "/one.yaml", text + "seeds: 1\n");
  testing::WriteText(dir + "/three.yaml", text + "seeds: 3\n");
  const CompareSpec one = LoadCompareSpec(dir + "/one.yaml", testing::Plugins());
  const CompareSpec three = LoadCompareSpec(dir + "/three.yaml", testing::Plugins());
  const auto rows_one = RunComparison(one, testing::Plugins());
  const auto rows_three = RunComparison(three, testing::Plugins());
  ASSERT_EQ(rows_one.size(), 2u);
  ASSERT_EQ(rows_three.size(), 6u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(rows_three[i].seed, 0);
    EXPECT_EQ(rows_three[i].validation.rms_mm, rows_one[i].validation.rms_mm);
  }
  EXPECT_NE(rows_three[2].validation.max_mm, rows_three[0].validation.max_mm);  // a fresh draw
  const std::string table = CompareTableMarkdown(three, rows_three);
  EXPECT_THAT(table, HasSubstr("3 seeds per row"));
  EXPECT_THAT(table, HasSubstr("- for uniform_workspace x 24, which formulation and solver: "));
  EXPECT_THAT(CompareTableMarkdown(one, rows_one), Not(HasSubstr("Recommendations")));
}

// The marker comparison over seeds: each seed its own renders, figures as intervals, one
// recommendation (small: 3 captures, 3 positions, 2 seeds).
TEST(MarkerCompare, SeedsGiveIntervalsAndARecommendation) {
  const std::string dir = testing::TempDirForThisTest("compare_solvers");
  testing::WriteText(dir + "/m.yaml",
                     "compare: markers\n"
                     "detectors:\n"
                     "  dot: {type: dot, diameter_mm: 10}\n"
                     "  aruco: {type: aruco, dictionary: DICT_4X4_50, marker_length_mm: 20, "
                     "marker_ids: [0]}\n"
                     "static_pose: {xyz: [10, -5, 450], rvec: [3.14159265, 0, 0]}\n"
                     "captures: 3\n"
                     "workspace: {positions: 3, depth_mm: [300, 600], lateral_mm: 120, "
                     "tilt_rad: 0.35}\n"
                     "render: {noise_sigma: 2, blur_sigma_px: 0.6, supersampling: 2}\n"
                     "seeds: 2\n");
  const MarkerComparisonSpec spec = LoadMarkerComparison(dir + "/m.yaml", testing::Plugins());
  const auto per_seed = CompareMarkersOverSeeds(spec, testing::Plugins());
  ASSERT_EQ(per_seed.size(), 2u);
  EXPECT_NE(per_seed[0][0].static_bias_mm, per_seed[1][0].static_bias_mm);  // new renders
  const std::string table = MarkerSeedsMarkdown(spec, per_seed);
  EXPECT_THAT(table, HasSubstr("2 seeds (1 to 2)"));
  EXPECT_THAT(table, HasSubstr("- for this rig, which detector: "));
  const std::string csv = MarkerSeedsCsv(spec, per_seed);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 2);
}

// A small comparison through the command line: 3 seeds, two solvers, both camera models.
TEST(CompareSolvers, EndToEndOnASmallSpec) {
  const std::string dir = testing::TempDirForThisTest("compare_solvers");
  testing::WriteText(dir + "/spec.yaml",
                     "compare: solvers\n"
                     "job: " +
                         testing::Source("configs/jobs/vsb_sim_b.yaml") +
                         "\n"
                         "simulation: " +
                         testing::Source("configs/simulations/ur3_two_cameras.yaml") +
                         "\n"
                         "solvers: {ceres_lm: {type: ceres_lm}, pinv: {type: jacobian_pinv}}\n"
                         "seeds: 3\n"
                         "output: " +
                         dir + "/out\n");
  const auto r = testing::RunCellmetry("compare " + dir + "/spec.yaml");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string table = testing::ReadText(dir + "/out/table.md");
  EXPECT_THAT(table, HasSubstr("| static_cameras | ceres_lm | "));
  EXPECT_THAT(table, HasSubstr("| per_frame | pinv | "));
  EXPECT_THAT(table, HasSubstr("3 seeds per row"));
  EXPECT_THAT(table, HasSubstr("- for this cell, static_cameras, which solver: "));
  EXPECT_THAT(table, HasSubstr("- for this cell, ceres_lm, which camera model: "));
  EXPECT_THAT(table, HasSubstr("/3 |"));  // converged count per row
  const std::string csv = testing::ReadText(dir + "/out/table.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 2 * 3);
}

TEST(CompareSolvers, AnUnknownKindListsEveryKind) {
  const std::string dir = testing::TempDirForThisTest("compare_solvers");
  testing::WriteText(dir + "/spec.yaml", "compare: solver\n");
  const auto r = testing::RunCellmetry("compare " + dir + "/spec.yaml");
  testing::ExpectOneLineError(r, "spec.yaml:1:10:", "unknown comparison 'solver'");
  for (const char* kind : {"kinematic", "markers", "physics", "solvers"}) {
    EXPECT_THAT(r.output, HasSubstr(kind));
  }
}

}  // namespace
}  // namespace cellmetry
