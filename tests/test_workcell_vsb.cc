// The real VSB recordings: the paper's expected answer on sim_b by every solver, the static
// camera model beating the per-frame model on exp_a's three real cameras, and sigma that covers
// the measured placement.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/result_io.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/estimation/noise_model.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

// `job_file` run with `solver_yaml`, `folds`-fold cross-validation, without each camera in turn
// only where `leave_cameras_out`, and without the cameras in `unused` at all.
WorkcellResult RunJob(const std::string& job_file, const std::string& solver_yaml, int folds,
                      bool compare = false, bool leave_cameras_out = false,
                      const std::set<std::string>& unused = {}) {
  Registry& registry = testing::Plugins();
  WorkcellJob job = LoadWorkcellJob(testing::Source(job_file), registry);
  job.problem.folds = folds;
  job.problem.compare_camera_models = compare;
  job.problem.leave_one_camera_out = leave_cameras_out;
  for (const std::string& camera : unused) job.problem.cameras[camera].use = false;
  const ConfigNode solver = ConfigNode::LoadString(solver_yaml, "solver");
  const Recording recording = ReadRecording(job.recording);
  return IdentifyWorkcell(job.problem, recording,
                          [&] { return registry.CreateSolver(solver["type"].AsString(), solver); });
}

using testing::Frame;

class SimB : public ::testing::TestWithParam<std::string> {};

// Issue: base within 1.5 mm per axis of (431, 555, -460), tool z within 1.5 mm of 66, by each
// solver from the default (closed-form) start.
TEST_P(SimB, FindsThePapersBaseAndTool) {
  const WorkcellResult r = RunJob("configs/jobs/vsb_sim_b.yaml", GetParam(), 0);
  const Pose base = Frame(r, "ur3.base").pose;
  EXPECT_NEAR(base.t.x(), 431.0, 1.5);
  EXPECT_NEAR(base.t.y(), 555.0, 1.5);
  EXPECT_NEAR(base.t.z(), -460.0, 1.5);
  EXPECT_NEAR(Frame(r, "tool").pose.t.z(), 66.0, 1.5);
  EXPECT_TRUE(r.solver.converged) << r.solver.stop_reason;
}

INSTANTIATE_TEST_SUITE_P(EverySolver, SimB,
                         ::testing::Values("type: ceres_lm", "type: jacobian_pinv",
                                           "{type: nlopt, algorithm: LD_LBFGS}",
                                           "{type: nlopt, algorithm: LN_BOBYQA}"));

TEST(ExpA, StaticCamerasPredictHeldOutPosesBetterThanPerFrameWorldTags) {
  const WorkcellResult r =
      RunJob("configs/jobs/vsb_exp_a_geometry.yaml", "type: ceres_lm", 5, true);
  ASSERT_EQ(r.held_out.folds, 5);
  ASSERT_TRUE(r.other_models.count("per_frame"));
  const double static_rms = r.held_out.total.norm;
  const double per_frame_rms = r.other_models.at("per_frame").total.norm;
  EXPECT_LT(static_rms, 0.85 * per_frame_rms) << static_rms << " vs " << per_frame_rms;
  // Beyond what the held-out poses' own scatter could give.
  const HeldOutGain per_frame_worse = CompareHeldOut(r.other_models.at("per_frame"), r.held_out);
  EXPECT_GT(per_frame_worse.gain_mm, 3 * per_frame_worse.standard_error_mm) << WorkcellSummary(r);
  // The repeatability floor is known from the 10 captures per pose and lies below both.
  double floor_sq = 0.0;
  int cameras = 0;
  for (const auto& [key, noise] : r.repeatability.entries) {
    if (key.second != "tool") continue;
    floor_sq += noise.position_mm.squaredNorm();
    ++cameras;
  }
  ASSERT_EQ(cameras, 3);
  EXPECT_LT(std::sqrt(floor_sq / cameras), static_rms);
  // And the summary says in words where the floor came from.
  EXPECT_THAT(WorkcellSummary(r),
              ::testing::HasSubstr("mm (spread of 10 repeated captures at each of 250 poses)\n"));
}

TEST(NoiseFloor, SaysInWordsWhereItCameFrom) {
  Recording exp_a = ReadRecording(testing::Source("tests/data/vsb/exp_a"));
  const NoiseModel all = EstimateRepeatability(exp_a);
  EXPECT_EQ(all.at("cam2", "tool").source, "spread of 10 repeated captures at each of 250 poses");
  EXPECT_EQ(all.at("cam2", "world").source, "spread of 2500 captures of a world-fixed target");
  // Keep 3 captures of pose 0 and every capture of poses 1 and 2: counts that differ, said so.
  std::set<int> kept;
  for (const auto& s : exp_a.samples) {
    if ((s.pose == 0 && s.id % 10 < 3) || s.pose == 1 || s.pose == 2) kept.insert(s.id);
  }
  std::vector<Observation> observations;
  for (const auto& o : exp_a.observations) {
    if (kept.count(o.sample)) observations.push_back(o);
  }
  exp_a.observations = observations;
  const NoiseModel few = EstimateRepeatability(exp_a);
  EXPECT_EQ(few.at("cam1", "tool").source,
            "spread of 3 to 10 repeated captures at each of 3 poses");
  EXPECT_EQ(few.at("cam1", "world").source, "spread of 23 captures of a world-fixed target");
}

// Sigma that covers the independent truth: the placement measured when the robot was
// set up, (431, 555, -460) mm, and the tool's 66 mm (exp_a); the simulator's own placement and
// tool (sim_b). Every base and tool coordinate within 3 sigma, for the best model and for the
// geometry alone, with the jobs' stated input uncertainties.
void ExpectCovers(const WorkcellResult& r, const std::string& job) {
  const FrameEstimate& base = Frame(r, "ur3.base");
  const FrameEstimate& tool = Frame(r, "tool");
  const Eigen::Vector3d placement(431.0, 555.0, -460.0);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(base.pose.t[i] - placement[i]), 3 * base.sigma_mm[i])
        << job << ": base "
        << "xyz"[i] << " = " << base.pose.t[i] << " +- " << base.sigma_mm[i];
  }
  EXPECT_LT(std::abs(tool.pose.t.z() - 66.0), 3 * tool.sigma_mm.z())
      << job << ": tool z = " << tool.pose.t.z() << " +- " << tool.sigma_mm.z();
  // The tool is a 66 mm offset along the flange's z axis: x and y are zero.
  for (int i = 0; i < 2; ++i) {
    EXPECT_LT(std::abs(tool.pose.t[i]), 3 * tool.sigma_mm[i])
        << job << ": tool "
        << "xy"[i] << " = " << tool.pose.t[i] << " +- " << tool.sigma_mm[i];
  }
}

TEST(RealRecordings, SigmaCoversTheMeasuredPlacement) {
  for (const char* job : {"configs/jobs/vsb_exp_a.yaml", "configs/jobs/vsb_exp_a_boards.yaml",
                          "configs/jobs/vsb_exp_a_geometry.yaml", "configs/jobs/vsb_sim_b.yaml"}) {
    const WorkcellResult r = RunJob(job, "type: ceres_lm", 0);
    ExpectCovers(r, job);
    if (std::string(job) != "configs/jobs/vsb_exp_a.yaml") continue;
    // The UR3 stands level within 3 mrad (a stated input): the data cannot tell its tilt from
    // the world tag's, so the prior decides both, and sigma is the prior's.
    const FrameEstimate& base = Frame(r, "ur3.base");
    EXPECT_NEAR(base.sigma_rad[0], 0.003, 1e-5);
    EXPECT_NEAR(base.sigma_rad[1], 0.003, 1e-5);
  }
}

// The best model on every camera subset of experiment A: each single camera and each pair.
// Every base coordinate and the tool's z within 3 sigma of the measured placement. One camera
// alone cannot tell the world board's printed size from its own distance to the board: held at
// nominal, that gauge put the base 12-32 mm off at up to 10 sigma; given the size's plausible
// 2 % as a 2-sigma prior, sigma carries it.
TEST(RealRecordings, EveryCameraSubsetCoversThePlacement) {
  const std::vector<std::set<std::string>> left_out = {
      {"cam2", "cam3"}, {"cam1", "cam3"}, {"cam1", "cam2"}, {"cam1"}, {"cam2"}, {"cam3"}};
  for (const std::set<std::string>& unused : left_out) {
    const std::string job = "configs/jobs/vsb_exp_a.yaml without " + *unused.begin() +
                            (unused.size() > 1 ? " and " + *unused.rbegin() : "");
    const WorkcellResult r =
        RunJob("configs/jobs/vsb_exp_a.yaml", "type: ceres_lm", 0, false, false, unused);
    EXPECT_EQ(r.unused_cameras.size(), unused.size()) << job;
    const FrameEstimate& base = Frame(r, "ur3.base");
    const FrameEstimate& tool = Frame(r, "tool");
    const Eigen::Vector3d placement(431.0, 555.0, -460.0);
    for (int i = 0; i < 3; ++i) {
      EXPECT_FALSE(base.undetermined[i]) << job;
      EXPECT_LT(std::abs(base.pose.t[i] - placement[i]), 3 * base.sigma_mm[i])
          << job << ": base "
          << "xyz"[i] << " = " << base.pose.t[i] << " +- " << base.sigma_mm[i];
    }
    EXPECT_LT(std::abs(tool.pose.t.z() - 66.0), 3 * tool.sigma_mm.z())
        << job << ": tool z = " << tool.pose.t.z() << " +- " << tool.sigma_mm.z();
  }
}

// Each camera of experiment A left out in turn, the best model: the cameras agree within the
// sigma of the difference (no camera flagged), and every base and tool coordinate is compared.
TEST(RealRecordings, EachCameraLeftOutAgreesWithTheOthersOnExperimentA) {
  const WorkcellResult r =
      RunJob("configs/jobs/vsb_exp_a.yaml", "type: ceres_lm", 0, false, /*leave_cameras_out=*/true);
  ASSERT_EQ(r.cameras_left_out.size(), 3u);
  for (const CameraLeftOut& c : r.cameras_left_out) {
    EXPECT_TRUE(c.error.empty()) << c.camera << ": " << c.error;
    EXPECT_FALSE(c.flagged()) << c.camera << ": " << c.worst << " " << c.worst_sigmas;
    EXPECT_LT(c.worst_sigmas, 3.0) << c.camera << ": " << c.worst;
    ASSERT_EQ(c.frames.size(), 2u);  // the base, the tool
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(c.frames[0].compared[i]) << c.camera;
  }
}

// The scoreboard's best model against the boards-only one (docs/real-data.md): with each
// camera's principal point the held-out positions fall by nearly half (6.1 -> 3.3 mm against a
// 1.49 mm floor) while the base stays within 5 mm of the measured placement and the tool within
// 2 mm of its 66 mm, as the issue asks of experiment A.
TEST(RealRecordings, PrincipalPointsHalveTheHeldOutErrorOnExperimentA) {
  const WorkcellResult boards = RunJob("configs/jobs/vsb_exp_a_boards.yaml", "type: ceres_lm", 5);
  const WorkcellResult best = RunJob("configs/jobs/vsb_exp_a.yaml", "type: ceres_lm", 5);
  ASSERT_EQ(best.held_out.folds, 5);
  EXPECT_LT(best.held_out.total.norm, 0.6 * boards.held_out.total.norm)
      << best.held_out.total.norm << " vs " << boards.held_out.total.norm;
  const Eigen::Vector3d placement(431.0, 555.0, -460.0);
  EXPECT_LT((Frame(best, "ur3.base").pose.t - placement).norm(), 5.0);
  EXPECT_NEAR(Frame(best, "tool").pose.t.z(), 66.0, 2.0);
}

// The answers BM_Identify times, pinned: the verdicts (what was held as
// unidentifiable, which rows were outliers) and every estimate and sigma part, as the code
// before the speed-ups computed them. Faster code must compute the same numbers, to 1e-6
// relative. CELLMETRY_PIN_ANSWERS=1 writes the files again (only for a deliberate change of what
// is computed, said so in its commit).
std::map<std::string, double> PinnedQuantities(const WorkcellResult& r) {
  std::map<std::string, double> out;
  for (const auto& u : r.unidentifiable) out["unidentifiable " + u.name] = 1.0;
  out["outliers"] = static_cast<double>(r.outliers.size());
  for (const auto& o : r.outliers) {
    out["outlier sample " + std::to_string(o.sample) + " " + o.camera + "/" + o.target + " " +
        o.kind] = 1.0;
  }
  for (const FrameEstimate& f : r.frames) {
    const Eigen::Vector3d rvec = RvecFromRotation(f.pose.R);
    for (int i = 0; i < 6; ++i) {
      const std::string name = f.name + "." + kFrameParameterNames[i];
      out[name + " value"] = i < 3 ? f.pose.t[i] : rvec[i - 3];
      out[name + " sigma"] = i < 3 ? f.sigma_mm[i] : f.sigma_rad[i - 3];
      out[name + " statistical"] = f.sigma_statistical[i];
      out[name + " systematic"] = f.sigma_systematic[i];
      out[name + " inputs"] = f.sigma_inputs[i];
    }
  }
  for (const ScalarEstimate& s : r.model_parameters) {
    out[s.name + " value"] = s.value;
    out[s.name + " sigma"] = s.sigma;
    out[s.name + " statistical"] = s.sigma_statistical;
    out[s.name + " systematic"] = s.sigma_systematic;
    out[s.name + " inputs"] = s.sigma_inputs;
  }
  return out;
}

// ((job, pinned answers), solver): each solver must reach the same minimum and verdicts.
using PinnedJob = std::pair<std::string, std::string>;
class PinnedAnswers : public ::testing::TestWithParam<std::tuple<PinnedJob, std::string>> {};

TEST_P(PinnedAnswers, AreComputedAgainToOnePartInAMillion) {
  const auto& [files, solver] = GetParam();
  const auto& [job, pinned_file] = files;
  const auto now = PinnedQuantities(RunJob(job, "type: " + solver, 0));
  const std::string path = testing::Source(pinned_file);
  if (std::getenv("CELLMETRY_PIN_ANSWERS") && solver == "ceres_lm") {
    std::ofstream out(path);
    out << "# " << job << ", ceres_lm, no cross-validation: tests/test_workcell_vsb.cc pins it\n";
    char line[64];
    for (const auto& [name, value] : now) {
      std::snprintf(line, sizeof(line), "%.17g", value);
      out << name << " = " << line << "\n";
    }
    GTEST_SKIP() << "wrote " << path;
  }
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::map<std::string, double> pinned;
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find(" = ");
    if (line.empty() || line[0] == '#' || eq == std::string::npos) continue;
    pinned[line.substr(0, eq)] = std::stod(line.substr(eq + 3));
  }
  ASSERT_GT(pinned.size(), 50u);
  for (const auto& [name, value] : pinned) {
    ASSERT_TRUE(now.count(name)) << job << ": " << name << " is gone";
    // A part of sigma is compared on the scale of the whole (a part at rounding level, 1e-13
    // of its sigma, has no sixth digit to keep); a value on its own scale or its sigma's.
    const auto sigma = pinned.find(name.substr(0, name.rfind(' ')) + " sigma");
    const double sigma_scale = sigma == pinned.end() ? 0.0 : std::abs(sigma->second);
    const double scale = std::max({std::abs(value), std::abs(now.at(name)), sigma_scale, 1e-12});
    EXPECT_LE(std::abs(now.at(name) - value), 1e-6 * scale)
        << job << ": " << name << " = " << now.at(name) << ", pinned " << value;
  }
  for (const auto& [name, value] : now) EXPECT_TRUE(pinned.count(name)) << job << ": new " << name;
}

INSTANTIATE_TEST_SUITE_P(
    VsbJobs, PinnedAnswers,
    ::testing::Combine(::testing::Values(PinnedJob("configs/jobs/vsb_sim_b.yaml",
                                                   "tests/data/vsb/pinned_answers_sim_b.txt"),
                                         PinnedJob("configs/jobs/vsb_exp_a_geometry.yaml",
                                                   "tests/data/vsb/pinned_answers_exp_a.txt")),
                       ::testing::Values(std::string("ceres_lm"), std::string("normal_lm"))));

}  // namespace
}  // namespace cellmetry
