// Camera subsets on simulation with a known truth: each camera left out agrees with the others
// within the sigma of the difference (and one with a concealed principal point does not), a
// camera the job does not use is left out whole, a gauge one camera cannot see is carried by
// its physics' plausible size, and a level base determines a tilted world tag with its sigma.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/result_io.h"
#include "cellmetry/cell/truth.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

// One UR3 on the VSB path, seen by the three cameras of experiment A, with `effects` (a
// simulation's `effects:` list) concealed in the measurements.
std::string ThreeCameraSimulation(unsigned seed, const std::string& effects = "") {
  return "simulation: workcell\nseed: " + std::to_string(seed) +
         "\nrepeats: 1\nrobots:\n  ur3:\n    model: " +
         testing::Source("configs/robots/ur3_vsb2020.yaml") +
         "\n    base: {xyz: [431, 555, -460], rvec: [0, 0, -0.0177]}\n"
         "    tools:\n      tool: {xyz: [0, 0.5, 66], rvec: [0, 0, 0]}\n"
         "    poses: {from_recording: " +
         testing::Source("tests/data/vsb/sim_b") +
         "}\n"
         "cameras:\n"
         "  cam1: {xyz: [745, 290, 986], rvec: [-2.6081, -1.2675, 0.5875]}\n"
         "  cam2: {xyz: [120, 1258, 739], rvec: [1.6523, 1.8133, -0.4370]}\n"
         "  cam3: {xyz: [-368, -336, 877], rvec: [-2.2208, 1.0610, -0.5030]}\n"
         "noise:\n  position_mm: [0.3, 0.3, 1.0]\n  rotation_rad: [0.002, 0.002, 0.004]\n" +
         effects;
}

struct Simulated {
  Recording recording;
  WorkcellTruth truth;
};

Simulated Simulate(const std::string& dir, const std::string& yaml) {
  testing::WriteText(dir + "/sim.yaml", yaml);
  const WorkcellSimulationSpec spec = LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins());
  Simulated out;
  out.recording = SimulateWorkcell(spec, &out.truth);
  return out;
}

// A job on the simulation: base and tool position, cameras in closed form; `extra` is more of
// the job's YAML (effects, cameras, priors).
WorkcellJob Job(const std::string& dir, const std::string& base = "{free: all}",
                const std::string& extra = "") {
  testing::WriteText(dir + "/job.yaml",
                     "job: workcell\nrecording: " + dir + "\noutput: " + dir +
                         "/fit\n"
                         "robots:\n  ur3:\n    model: " +
                         testing::Source("configs/robots/ur3_vsb2020.yaml") +
                         "\n    base: " + base + "\n    tools:\n      tool: {free: [x, y, z]}\n" +
                         extra + "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n");
  return LoadWorkcellJob(dir + "/job.yaml", testing::Plugins(), /*recording_must_exist=*/false);
}

// Every difference a camera left out shows, in sigmas of the difference, on 12 noisy
// simulations of a three-camera cell whose model is right: about standard normal, as the
// sigma claims (RMS near 1, nearly every one within 3).
TEST(CameraLeftOut, DifferencesAreStandardNormalWhereTheModelIsRight) {
  const std::string dir = testing::TempDirForThisTest("loco");
  std::vector<double> z;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    const Simulated sim = Simulate(dir, ThreeCameraSimulation(seed));
    const WorkcellJob job = Job(dir);
    ASSERT_TRUE(job.problem.leave_one_camera_out);  // a job's default
    const WorkcellResult r = testing::Identify(job, sim.recording);
    ASSERT_EQ(r.cameras_left_out.size(), 3u);
    for (const CameraLeftOut& c : r.cameras_left_out) {
      ASSERT_TRUE(c.error.empty()) << c.error;
      for (const FrameDifference& d : c.frames) {
        for (int i = 0; i < 6; ++i) {
          if (d.compared[i]) z.push_back(d.difference[i] / d.sigma[i]);
        }
      }
    }
  }
  ASSERT_GT(z.size(), 200u);
  double ss = 0.0;
  int inside = 0;
  for (double v : z) {
    ss += v * v;
    inside += std::abs(v) <= 3.0 ? 1 : 0;
  }
  const double rms = std::sqrt(ss / static_cast<double>(z.size()));
  EXPECT_GT(rms, 0.6) << "the sigma of a difference is too wide";
  EXPECT_LT(rms, 1.5) << "the sigma of a difference is too narrow";
  EXPECT_GE(inside, 0.95 * static_cast<double>(z.size())) << inside << " of " << z.size();
}

// cam2's principal point off by 15 mrad, which the job does not model: without cam2 the base
// moves by more than the difference's sigma allows, and the run says which camera.
TEST(CameraLeftOut, ACameraWithAConcealedPrincipalPointIsFlagged) {
  const std::string dir = testing::TempDirForThisTest("loco_principal");
  const Simulated sim = Simulate(
      dir, ThreeCameraSimulation(3,
                                 "effects:\n  - {effect: {type: camera_intrinsics, cameras: "
                                 "[cam2], terms: [principal]}, values: {cam2.principal_x: "
                                 "0.015}}\n"));
  const WorkcellResult r = testing::Identify(Job(dir), sim.recording);
  ASSERT_EQ(r.cameras_left_out.size(), 3u);
  const CameraLeftOut& without_cam2 = r.cameras_left_out[1];
  EXPECT_EQ(without_cam2.camera, "cam2");
  EXPECT_TRUE(without_cam2.flagged()) << without_cam2.worst << " " << without_cam2.worst_sigmas;
  EXPECT_THAT(r.warnings, ::testing::Contains(::testing::HasSubstr(
                              "cam2 disagrees with the other cameras beyond the uncertainty")));
  const std::string summary = WorkcellSummary(r);
  EXPECT_THAT(summary, ::testing::HasSubstr("each camera left out"));
  EXPECT_THAT(summary, ::testing::HasSubstr("FLAGGED"));
  const nlohmann::json j = WorkcellResultJson(r);
  ASSERT_EQ(j["cameras_left_out"].size(), 3u);
  EXPECT_EQ(j["cameras_left_out"][1]["camera"], "cam2");
  EXPECT_TRUE(j["cameras_left_out"][1]["flagged"].get<bool>());
}

// `cameras: {cam2: {use: false}}`: cam2's observations are left out whole (no frame, no rows),
// the rows keep their numbers in the recording, and the result says which camera was not used.
TEST(CameraLeftOut, ACameraTheJobDoesNotUseIsLeftOutWhole) {
  const std::string dir = testing::TempDirForThisTest("use_false");
  const Simulated sim = Simulate(dir, ThreeCameraSimulation(4));
  const WorkcellJob job = Job(dir, "{free: all}", "cameras:\n  cam2: {use: false}\n");
  const WorkcellResult r = testing::Identify(job, sim.recording);
  EXPECT_EQ(r.unused_cameras, std::vector<std::string>{"cam2"});
  for (const auto& f : r.frames) EXPECT_NE(f.name, "cam2");
  ASSERT_FALSE(r.residuals.empty());
  for (const ResidualRow& row : r.residuals) {
    EXPECT_NE(row.camera, "cam2");
    const Observation& obs = sim.recording.observations.at(static_cast<size_t>(row.observation));
    EXPECT_EQ(obs.camera, row.camera);
    EXPECT_EQ(obs.target, row.target);
  }
  // Two cameras left: each is left out in turn against the pair.
  EXPECT_EQ(r.cameras_left_out.size(), 2u);
}

// One camera alone cannot tell the world board's printed size from its own distance to it.
// Held at nominal, that gauge would leave sigma; given the size's plausible 2 % as a 2-sigma
// prior, sigma carries it, and the truth (the world board printed 1 % large) is inside 3 sigma.
TEST(GaugePrior, OneCameraTakesTheWorldBoardsSizeFromItsPlausibleSize) {
  const std::string dir = testing::TempDirForThisTest("gauge_prior");
  const Simulated sim =
      Simulate(dir, ThreeCameraSimulation(5,
                                          "effects:\n  - {effect: {type: target_scale, targets: "
                                          "[world]}, values: {world.scale: 0.01}}\n"));
  const WorkcellJob job = Job(dir, "{free: all}",
                              "cameras:\n  cam2: {use: false}\n  cam3: {use: false}\n"
                              "effects:\n  - {type: target_scale, targets: [tool, world]}\n");
  const WorkcellResult r = testing::Identify(job, sim.recording);
  bool world_scale = false;
  for (const auto& u : r.unidentifiable) {
    if (u.name != "camera.target_scale.world.scale") continue;
    world_scale = true;
    EXPECT_DOUBLE_EQ(u.prior_sigma, 0.01);  // plausible 0.02 as 2 sigma
    EXPECT_FALSE(u.moves_with.empty());
  }
  EXPECT_TRUE(world_scale) << "the world board's size was not found in a gauge";
  const FrameEstimate& base = testing::Frame(r, "ur3.base");
  const Eigen::Vector3d truth(431, 555, -460);
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(base.undetermined[i]);
    EXPECT_LT(std::abs(base.pose.t[i] - truth[i]), 3 * base.sigma_mm[i]) << "xyz"[i];
  }
  // The prior's sigma is a stated input: the chi-square scale does not widen it.
  for (const auto& s : r.model_parameters) {
    if (s.name == "camera.target_scale.world.scale") {
      EXPECT_NEAR(s.sigma, 0.01, 1e-6);
    }
  }
  EXPECT_THAT(WorkcellSummary(r),
              ::testing::HasSubstr("not determined by this data: camera.target_scale.world.scale, "
                                   "taken as 0 +- 0.01"));
}

// Without a prior to give, a gauge is held, and what moves with it says so instead of a sigma:
// the first link's length d1 and the base's height move together (no pose tells them apart).
TEST(GaugePrior, WithoutAPlausibleSizeTheHoldIsSaidAndItsPartnersAreUndetermined) {
  const std::string dir = testing::TempDirForThisTest("gauge_held");
  const Simulated sim = Simulate(dir, ThreeCameraSimulation(6));
  // j1.d with the base free: by convention it puts the base frame (next test); stripped of that
  // convention here, it is a parameter the data cannot determine and nothing else decides.
  WorkcellJob job = Job(dir, "{free: all}\n    free_model: [j1.d]");
  for (Parameter& p : job.problem.robots[0].model_parameters) p.convention.clear();
  const WorkcellResult r = testing::Identify(job, sim.recording);
  ASSERT_FALSE(r.unidentifiable.empty());
  const UnidentifiableParameter& held = r.unidentifiable.front();
  EXPECT_EQ(held.prior_sigma, 0.0);
  ASSERT_FALSE(held.moves_with.empty()) << held.name;
  const std::string partner = held.moves_with.front().name;
  bool marked = false;
  for (const auto& f : r.frames) {
    for (int i = 0; i < 6; ++i) {
      marked |= f.undetermined[i] && f.name + "." + kFrameParameterNames[i] == partner;
    }
  }
  for (const auto& s : r.model_parameters) marked |= s.undetermined && s.name == partner;
  EXPECT_TRUE(marked) << partner << " moves with " << held.name << " but is not marked";
  const std::string summary = WorkcellSummary(r);
  EXPECT_THAT(summary, ::testing::HasSubstr("undetermined"));
  EXPECT_THAT(summary, ::testing::HasSubstr("are not determined by this data either"));
  EXPECT_FALSE(WorkcellResultJson(r)["undetermined"].empty());
}

// The same hold where the parameter's nominal value is a convention (joint 1's d puts the base
// frame): held first, said as a convention, and its partner (the base's z) given relative to it
// with its sigma, not undetermined.
TEST(GaugePrior, AConventionIsHeldAndSaidAndItsPartnersKeepTheirSigma) {
  const std::string dir = testing::TempDirForThisTest("gauge_convention");
  const Simulated sim = Simulate(dir, ThreeCameraSimulation(6));
  const WorkcellJob job = Job(dir, "{free: all}\n    free_model: [j1.d]");
  const WorkcellResult r = testing::Identify(job, sim.recording);
  ASSERT_EQ(r.unidentifiable.size(), 1u);
  EXPECT_EQ(r.unidentifiable.front().name, "ur3.model.j1.d");
  EXPECT_FALSE(r.unidentifiable.front().convention.empty());
  for (const auto& f : r.frames) {
    for (int i = 0; i < 6; ++i) EXPECT_FALSE(f.undetermined[i]) << f.name;
  }
  EXPECT_GT(testing::Frame(r, "ur3.base").sigma_mm.z(), 0.0);
  EXPECT_THAT(WorkcellSummary(r), ::testing::HasSubstr("held at nominal by convention"));
  EXPECT_TRUE(WorkcellResultJson(r)["undetermined"].empty());
}

// The world tag glued 5 mrad off level, the UR3 standing level: with the level prior (3 mrad)
// the tag's tilt is determined, with the prior's sigma reaching it, and the truth inside 3 sigma.
TEST(LevelPrior, DeterminesATiltedWorldTagWithItsSigma) {
  const std::string dir = testing::TempDirForThisTest("level");
  const std::string yaml = ThreeCameraSimulation(7,
                                                 "effects:\n  - {effect: {type: world_frame}, "
                                                 "values: {world_frame.tilt_x: 0.005, "
                                                 "world_frame.tilt_y: -0.004}}\n");
  const Simulated sim = Simulate(dir, yaml);
  const WorkcellJob job =
      Job(dir, "{free: all, level: {sigma_rad: 0.003}}", "effects:\n  - {type: world_frame}\n");
  ASSERT_TRUE(job.problem.robots[0].level_sigma_rad.has_value());
  const WorkcellResult r = testing::Identify(job, sim.recording);
  EXPECT_TRUE(r.unidentifiable.empty()) << r.unidentifiable.front().name;
  const FrameEstimate& base = testing::Frame(r, "ur3.base");
  // The data cannot tell the base's tilt from the tag's: the prior decides both, with its sigma.
  EXPECT_NEAR(base.sigma_rad[0], 0.003, 3e-4);
  EXPECT_NEAR(base.sigma_rad[1], 0.003, 3e-4);
  for (const auto& s : r.model_parameters) {
    const double truth = s.name == "camera.world_frame.world_frame.tilt_x"   ? 0.005
                         : s.name == "camera.world_frame.world_frame.tilt_y" ? -0.004
                                                                             : NAN;
    if (std::isnan(truth)) continue;
    EXPECT_LT(std::abs(s.value - truth), 3 * s.sigma) << s.name << " = " << s.value;
    EXPECT_GT(s.sigma, 0.002) << s.name << ": the level prior's sigma must reach it";
  }
}

TEST(LevelPrior, NeedsTheBasesTiltFree) {
  const std::string dir = testing::TempDirForThisTest("level_held");
  const InputError e = testing::CatchInputError(
      [&] { Job(dir, "{free: [x, y, z, rz], level: {sigma_rad: 0.003}}"); });
  EXPECT_THAT(e.what(), ::testing::HasSubstr("a level prior needs the base's rotation about x "
                                             "and y free"));
}

}  // namespace
}  // namespace cellmetry
