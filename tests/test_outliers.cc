// Gross outliers (outliers.h) on a simulated two-camera UR3 cell: with +20 mm on a target's
// measured position in 2 % or 10 % of the poses (the tool's, or the world board's), or a
// 0.2 rad error in the world board's rotation, no base or tool coordinate moves by more than its
// clean sigma, and the observations listed are the corrupted ones (precision and recall 1). At
// 10 % the plain fit alone is pulled so far that the outliers hide in its inflated scale
// (checked: with `outliers: plain` the base moves by several sigma); the robust first fit finds
// them. On clean data nothing is listed and the answer is the plain fit's to 1e-9.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>
#include <tuple>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/outliers.h"
#include "cellmetry/cell/result_io.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "residual_rows.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

constexpr const char* kFrames[] = {"ur3.base", "tool"};

class Outliers : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string dir = testing::TempDirForThisTest("outliers");
    std::string sim =
        testing::ReadText(testing::Source("configs/simulations/ur3_two_cameras.yaml"));
    sim = testing::ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml",
                               testing::Source("configs/robots/ur3_vsb2020.yaml"));
    sim = testing::ReplaceOnce(sim, "../../tests/data/vsb/sim_b",
                               testing::Source("tests/data/vsb/sim_b"));
    testing::WriteText(dir + "/sim.yaml", sim);
    clean_ =
        SimulateWorkcell(LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins()), nullptr);
    testing::WriteText(dir + "/job.yaml",
                       "job: workcell\nrecording: " + dir + "/none\nrobots:\n  ur3:\n    model: " +
                           testing::Source("configs/robots/ur3_vsb2020.yaml") +
                           "\n    base: {free: all}\n    tools:\n      tool: {free: [x, y, z]}\n" +
                           testing::kTwoCameraNoiseYaml +
                           "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n");
    job_ = LoadWorkcellJob(dir + "/job.yaml", testing::Plugins(), false);
  }

  WorkcellResult Identify(const Recording& recording,
                          OutlierTest test = OutlierTest::kRobust) const {
    WorkcellJob job = job_;
    job.problem.outlier_test = test;
    return testing::Identify(job, recording);
  }

  // `clean_` with `corrupt` applied to the observations of `target` in the poses where
  // pose % period == 3; their sample ids in `bad`.
  Recording Corrupted(const std::string& target, int period,
                      const std::function<void(Observation&)>& corrupt, std::set<int>* bad) const {
    Recording out = clean_;
    for (const auto& s : out.samples) {
      if (s.pose % period == 3) bad->insert(s.id);
    }
    for (auto& obs : out.observations) {
      if (obs.target == target && bad->count(obs.sample)) corrupt(obs);
    }
    return out;
  }

  // The largest move of a free base or tool coordinate from the clean answer, in clean sigma.
  static double LargestMoveInSigma(const WorkcellResult& clean, const WorkcellResult& r) {
    double largest = 0.0;
    for (const char* name : kFrames) {
      const FrameEstimate& a = testing::Frame(clean, name);
      const FrameEstimate& b = testing::Frame(r, name);
      for (int i = 0; i < 3; ++i) {
        if (a.held[i]) continue;
        largest = std::max(largest, std::abs(b.pose.t[i] - a.pose.t[i]) / a.sigma_mm[i]);
      }
    }
    return largest;
  }

  // Every free base and tool coordinate within its clean sigma; the samples listed are `bad`.
  void ExpectFound(const WorkcellResult& clean, const WorkcellResult& r,
                   const std::set<int>& bad) const {
    std::set<int> flagged;
    for (const auto& o : r.outliers) flagged.insert(o.sample);
    int true_positives = 0;
    for (int s : flagged) true_positives += bad.count(s) ? 1 : 0;
    const double precision = flagged.empty() ? 1.0 : double(true_positives) / flagged.size();
    const double recall = double(true_positives) / bad.size();
    EXPECT_EQ(precision, 1.0) << flagged.size() << " samples flagged, " << true_positives
                              << " of them corrupted";
    EXPECT_EQ(recall, 1.0) << true_positives << " of " << bad.size() << " corrupted found";
    EXPECT_LE(LargestMoveInSigma(clean, r), 1.0);
    for (const char* name : kFrames) {
      const FrameEstimate& a = testing::Frame(clean, name);
      const FrameEstimate& b = testing::Frame(r, name);
      for (int i = 0; i < 3; ++i) {
        if (a.held[i]) continue;
        EXPECT_LE(std::abs(b.pose.t[i] - a.pose.t[i]), a.sigma_mm[i])
            << name << " "
            << "xyz"[i] << ": " << a.pose.t[i] << " -> " << b.pose.t[i];
      }
    }
  }

  Recording clean_;
  WorkcellJob job_;
};

void Plus20MmInX(Observation& obs) { obs.position_mm.x() += 20.0; }

TEST_F(Outliers, OnCleanDataNothingIsListedAndTheAnswerIsThePlainFits) {
  const WorkcellResult robust = Identify(clean_);
  const WorkcellResult plain = Identify(clean_, OutlierTest::kPlain);
  EXPECT_TRUE(robust.outliers.empty()) << robust.outliers.size() << " flagged on clean data";
  ASSERT_EQ(robust.frames.size(), plain.frames.size());
  for (size_t f = 0; f < plain.frames.size(); ++f) {
    const FrameEstimate& a = plain.frames[f];
    const FrameEstimate& b = robust.frames[f];
    EXPECT_EQ(a.name, b.name);
    EXPECT_LE((a.pose.t - b.pose.t).cwiseAbs().maxCoeff(), 1e-9) << a.name;
    EXPECT_LE((a.pose.R - b.pose.R).cwiseAbs().maxCoeff(), 1e-9) << a.name;
    EXPECT_LE((a.sigma_mm - b.sigma_mm).cwiseAbs().maxCoeff(), 1e-9) << a.name;
  }
}

TEST_F(Outliers, GrossErrorsInTwoPercentOfPosesMoveNothingByMoreThanItsCleanSigma) {
  const WorkcellResult clean = Identify(clean_);
  std::set<int> bad;
  const WorkcellResult r = Identify(Corrupted("tool", 50, Plus20MmInX, &bad));
  ExpectFound(clean, r, bad);
}

TEST_F(Outliers, TenPercentOnTheToolMoveNothingByMoreThanItsCleanSigma) {
  const WorkcellResult clean = Identify(clean_);
  std::set<int> bad;
  const Recording corrupted = Corrupted("tool", 10, Plus20MmInX, &bad);
  // Not a vacuous check: without the test the base moves far, and the plain fit's test alone
  // does not rescue it.
  const double off = LargestMoveInSigma(clean, Identify(corrupted, OutlierTest::kOff));
  const double plain = LargestMoveInSigma(clean, Identify(corrupted, OutlierTest::kPlain));
  EXPECT_GT(off, 5.0);
  EXPECT_GT(plain, 1.0);
  const WorkcellResult robust = Identify(corrupted);
  std::printf(
      "%zu of %zu samples corrupted; largest move in clean sigma: no test %.1f, plain "
      "fit's test %.1f, robust first fit %.2f\n",
      bad.size(), clean_.samples.size(), off, plain, LargestMoveInSigma(clean, robust));
  ExpectFound(clean, robust, bad);
}

// residuals.csv numbers each row by its observation in the user's recording, also when some
// were left out as outliers (the fit ran on fewer): each row names the sample, camera and
// target of the observation it points at, and none points at an outlier.
TEST_F(Outliers, ResidualRowsPointAtTheRecordingsObservations) {
  std::set<int> bad;
  const Recording corrupted = Corrupted("tool", 10, Plus20MmInX, &bad);
  const WorkcellResult r = Identify(corrupted);
  ASSERT_FALSE(r.outliers.empty());
  std::set<std::tuple<int, std::string, std::string>> left_out;  // built in memory: no lines
  for (const auto& o : r.outliers) left_out.insert({o.sample, o.camera, o.target});
  for (const ResidualRow& row : r.residuals) {
    ASSERT_LT(size_t(row.observation), corrupted.observations.size());
    const Observation& obs = corrupted.observations[row.observation];
    ASSERT_EQ(obs.sample, row.sample);
    ASSERT_EQ(obs.camera, row.camera);
    ASSERT_EQ(obs.target, row.target);
    ASSERT_FALSE(left_out.count({obs.sample, obs.camera, obs.target}))
        << "row points at an outlier: sample " << obs.sample << " " << obs.camera;
  }
}

// With the outlier test on the plain fit only, the identification again without the outliers
// is timed as a second pass: the summary's time line says so, and result.json keeps its stages
// apart (docs/formats.md).
TEST_F(Outliers, TheSecondPassIsTimedApart) {
  std::set<int> bad;
  const WorkcellResult r = Identify(Corrupted("tool", 50, Plus20MmInX, &bad), OutlierTest::kPlain);
  ASSERT_FALSE(r.outliers.empty());
  EXPECT_NE(WorkcellSummary(r).find("over 2 passes (outliers left out)"), std::string::npos)
      << WorkcellSummary(r);
  const nlohmann::json json = WorkcellResultJson(r);
  int first = 0, again = 0;
  for (const auto& stage : json["stages"]) {
    const std::string name = stage["stage"];
    (name.rfind("again_without_outliers/", 0) == 0 ? again : first)++;
  }
  EXPECT_GT(first, 0);
  EXPECT_GT(again, 0);
}

TEST_F(Outliers, TenPercentOnTheWorldBoardMoveNothingByMoreThanItsCleanSigma) {
  const WorkcellResult clean = Identify(clean_);
  std::set<int> bad;
  const Recording corrupted = Corrupted("world", 10, Plus20MmInX, &bad);
  ExpectFound(clean, Identify(corrupted), bad);
}

TEST_F(Outliers, TenPercentOfWorldBoardRotationsMoveNothingByMoreThanItsCleanSigma) {
  const WorkcellResult clean = Identify(clean_);
  std::set<int> bad;
  const Recording corrupted = Corrupted(
      "world", 10,
      [](Observation& obs) {
        ASSERT_TRUE(obs.rvec.has_value());
        obs.rvec->x() += 0.2;
      },
      &bad);
  ExpectFound(clean, Identify(corrupted), bad);
}

// The robust first fit tests a problem's blocks and residuals without making the result's rows
// (outliers.h): the same scales and the same outliers as the rows made from them, here at the
// clean answer with 20 mm on the tool in 10 % of the poses (positions and rotations, priors
// after the measurements).
TEST_F(Outliers, AProblemsBlocksAreTestedAsTheRowsMadeFromThem) {
  std::set<int> bad;
  const Recording corrupted = Corrupted("tool", 10, Plus20MmInX, &bad);
  const WorkcellProblem& spec = job_.problem;
  const WorkcellData data = PrepareWorkcellData(spec, corrupted);
  const NoiseModel noise = BuildNoiseModel(corrupted, spec.noise);
  auto assembled = AssembleWorkcell(spec, corrupted, data, noise, Identify(clean_).estimate);
  Problem& problem = assembled->problem;
  Eigen::VectorXd whitened;
  ASSERT_TRUE(problem.EvaluateSparse(&whitened, nullptr));
  const std::vector<ResidualRow> rows = ResidualRows(*assembled, nullptr);  // residuals.csv's
  ASSERT_GT(rows.size(), 100u);
  EXPECT_EQ(RobustScales(*assembled, whitened), RobustScales(rows));
  const std::vector<Outlier> from_rows = FindOutliers(rows, corrupted);
  const std::vector<Outlier> from_problem = FindOutliers(*assembled, whitened, corrupted);
  ASSERT_FALSE(from_rows.empty());
  ASSERT_EQ(from_problem.size(), from_rows.size());
  for (size_t i = 0; i < from_rows.size(); ++i) {
    EXPECT_EQ(from_problem[i].sample, from_rows[i].sample);
    EXPECT_EQ(from_problem[i].camera, from_rows[i].camera);
    EXPECT_EQ(from_problem[i].target, from_rows[i].target);
    EXPECT_EQ(from_problem[i].kind, from_rows[i].kind);
    EXPECT_EQ(from_problem[i].score, from_rows[i].score);
  }
}

}  // namespace
}  // namespace cellmetry
