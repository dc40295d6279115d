// Eye in hand: a camera riding on a UR3's flange looks at the board that defines the world
// (configs/simulations/ur3_eye_in_hand.yaml, configs/jobs/ur3_eye_in_hand.yaml). The camera's
// frame on the flange (T_flange_camera, `ur3.wrist`) and the base come back within 3 sigma of
// the truth with sigma under a millimetre and a milliradian; the closed-form start solves exact
// AX = XB data; the residual's Jet derivatives match central differences; and what the setting
// does not allow is refused in words.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include <ceres/dynamic_autodiff_cost_function.h>

#include "cellmetry/basics/error.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/formats/config_node.h"
#include "eye_in_hand_residual.h"
#include "hand_eye_start.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

const char kSimulation[] = "configs/simulations/ur3_eye_in_hand.yaml";
const char kJob[] = "configs/jobs/ur3_eye_in_hand.yaml";

// Each coordinate's error in its own sigma, printed; held to 3 sigma, and sigma to below 1 mm
// and 1 mrad (an honest, not an absurdly wide, sigma).
void ExpectWithinThreeSigma(const FrameEstimate& fitted, const Pose& truth) {
  const Eigen::Vector3d turn = RvecFromRotation(fitted.pose.R * truth.R.transpose());
  for (int i = 0; i < 3; ++i) {
    const double dt = fitted.pose.t[i] - truth.t[i];
    std::cerr << fitted.name << " "
              << "xyz"[i] << ": " << dt << " mm = " << dt / fitted.sigma_mm[i] << " sigma (sigma "
              << fitted.sigma_mm[i] << " mm); r"
              << "xyz"[i] << ": " << turn[i] * 1e3 << " mrad = " << turn[i] / fitted.sigma_rad[i]
              << " sigma (sigma " << fitted.sigma_rad[i] * 1e3 << " mrad)\n";
    EXPECT_LT(std::abs(dt), 3 * fitted.sigma_mm[i]) << fitted.name << " "
                                                    << "xyz"[i];
    EXPECT_LT(std::abs(turn[i]), 3 * fitted.sigma_rad[i]) << fitted.name << " r"
                                                          << "xyz"[i];
    EXPECT_GT(fitted.sigma_mm[i], 0.0);
    EXPECT_LT(fitted.sigma_mm[i], 1.0);
    EXPECT_GT(fitted.sigma_rad[i], 0.0);
    EXPECT_LT(fitted.sigma_rad[i], 1e-3);
  }
}

TEST(EyeInHand, TheCameraOnTheFlangeAndTheBaseComeBackWithinThreeSigma) {
  const WorkcellSimulationSpec spec =
      LoadWorkcellSimulation(testing::Source(kSimulation), testing::Plugins());
  const Recording recording = SimulateWorkcell(spec, nullptr);
  EXPECT_EQ(recording.camera_mounts.at("wrist"), "ur3");
  const WorkcellJob job = LoadWorkcellJob(testing::Source(kJob), testing::Plugins(),
                                          /*recording_must_exist=*/false);
  ValidateJobAgainstRecording(job, recording);
  const WorkcellResult result = testing::Identify(job, recording);
  const FrameEstimate& camera = testing::Frame(result, "ur3.wrist");
  EXPECT_EQ(camera.parent, "ur3.flange");
  ExpectWithinThreeSigma(camera, spec.robots[0].T_flange_camera.at("wrist"));
  ExpectWithinThreeSigma(testing::Frame(result, "ur3.base"), spec.robots[0].T_world_base);
}

// simulate, run, evaluate and the report on the command line, as the job's header says.
TEST(EyeInHand, SimulateRunAndEvaluateOnTheCommandLine) {
  const std::string dir = testing::TempDirForThisTest("eye_in_hand");
  const auto simulated =
      testing::RunCellmetry("simulate " + testing::Source(kSimulation) + " -o " + dir + "/rec");
  ASSERT_EQ(simulated.exit_code, 0) << simulated.output;
  const std::string job_text = testing::ReadText(testing::Source(kJob));
  std::string job =
      testing::ReplaceOnce(job_text, "../../results/ur3_eye_in_hand\n", dir + "/rec\n");
  job = testing::ReplaceOnce(job, "../../results/ur3_eye_in_hand_fit", dir + "/fit");
  job = testing::ReplaceOnce(job, "../robots/ur3_vsb2020.yaml",
                             testing::Source("configs/robots/ur3_vsb2020.yaml"));
  testing::WriteText(dir + "/job.yaml", job);
  const auto run = testing::RunCellmetry("run " + dir + "/job.yaml");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(testing::ReadText(dir + "/fit/result.yaml").find("ur3.wrist"), std::string::npos);
  EXPECT_NE(testing::ReadText(dir + "/fit/report.html").find("ur3.wrist"), std::string::npos);
  const auto evaluated =
      testing::RunCellmetry("evaluate " + dir + "/fit " + dir + "/rec/truth.yaml");
  ASSERT_EQ(evaluated.exit_code, 0) << evaluated.output;
  EXPECT_NE(evaluated.output.find("ur3.wrist"), std::string::npos) << evaluated.output;
}

TEST(EyeInHand, ParkAndMartinSolvesExactMotions) {
  const Pose X{RotationFromRvec(Eigen::Vector3d(0.3, -0.2, 1.1).data()),
               Eigen::Vector3d(12, -40, 55)};
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 0.5);
  std::vector<Pose> A, B;
  for (int k = 0; k < 6; ++k) {
    const Eigen::Vector3d r(n(rng), n(rng), n(rng));
    const Pose a{RotationFromRvec(r.data()), Eigen::Vector3d(100 * n(rng), 100 * n(rng), 50)};
    A.push_back(a);
    B.push_back(X.inverse() * a * X);  // A X = X B
  }
  const auto solved = SolveHandEye(A, B);
  ASSERT_TRUE(solved);
  EXPECT_LT((solved->R - X.R).norm(), 1e-9);
  EXPECT_LT((solved->t - X.t).norm(), 1e-7);
  // Turns about one axis alone leave X undetermined: refused.
  std::vector<Pose> A1, B1;
  for (double angle : {0.2, 0.5, -0.4}) {
    const Eigen::Vector3d r(0, 0, angle);
    A1.push_back(Pose{RotationFromRvec(r.data()), Eigen::Vector3d(angle, 0, 0)});
    B1.push_back(X.inverse() * A1.back() * X);
  }
  EXPECT_FALSE(SolveHandEye(A1, B1));
}

// The Jet derivatives (eye_in_hand_residual.h) against central differences, with the model free.
TEST(EyeInHand, JetDerivativesMatchCentralDifferences) {
  const ConfigNode config =
      ConfigNode::LoadFile(testing::Source("configs/robots/ur3_vsb2020.yaml"));
  const auto model = testing::Plugins().CreateRobotModel("serial_mdh", config);
  std::vector<double> params;
  for (const auto& p : model->parameters()) params.push_back(p.nominal);
  const Pose measured{RotationFromRvec(Eigen::Vector3d(3.0, 0.1, -0.2).data()),
                      Eigen::Vector3d(10, -20, 300)};
  const Eigen::Matrix3d R_base = RotationFromRvec(Eigen::Vector3d(0.1, 0.2, 0.7).data());
  const Eigen::Matrix3d R_cam = RotationFromRvec(Eigen::Vector3d(-0.3, 0.1, 0.4).data());
  for (Compared what : {Compared::kPosition, Compared::kRotation}) {
    const TargetComparison comparison(what, measured, Eigen::Vector3d(0.1, 0.2, 0.4));
    auto* functor = new EyeInHandResidual(comparison, R_base, R_cam, model.get(),
                                          {0.1, -1.4, 1.5, -1.7, -1.5, 0.2});
    ceres::DynamicAutoDiffCostFunction<EyeInHandResidual, kJetStride> cost(functor);
    std::vector<std::vector<double>> values = {
        {300, 110, 5, 0.01, -0.02, 0.03}, {1, 60, 40, 0.2, -0.1, 0.05}, params};
    for (const auto& v : values) cost.AddParameterBlock(static_cast<int>(v.size()));
    cost.SetNumResiduals(3);
    std::vector<const double*> blocks;
    for (const auto& v : values) blocks.push_back(v.data());
    std::vector<std::vector<double>> jacobians;
    std::vector<double*> jacobian_ptrs;
    for (const auto& v : values) jacobians.emplace_back(3 * v.size());
    for (auto& j : jacobians) jacobian_ptrs.push_back(j.data());
    double r[3];
    ASSERT_TRUE(cost.Evaluate(blocks.data(), r, jacobian_ptrs.data()));
    for (size_t b = 0; b < values.size(); ++b) {
      for (size_t k = 0; k < values[b].size(); ++k) {
        const double h = 1e-6;
        double plus[3], minus[3];
        values[b][k] += h;
        ASSERT_TRUE(cost.Evaluate(blocks.data(), plus, nullptr));
        values[b][k] -= 2 * h;
        ASSERT_TRUE(cost.Evaluate(blocks.data(), minus, nullptr));
        values[b][k] += h;
        for (int i = 0; i < 3; ++i) {
          const double numeric = (plus[i] - minus[i]) / (2 * h);
          EXPECT_NEAR(jacobians[b][i * values[b].size() + k], numeric,
                      1e-5 * (1.0 + std::abs(numeric)))
              << "block " << b << " entry " << k << " row " << i;
        }
      }
    }
  }
}

// The simulated recording and the job, written to `dir`, with `edit` applied to the job text.
void WriteCell(const std::string& dir, const std::string& from, const std::string& to,
               Recording* recording) {
  const WorkcellSimulationSpec spec =
      LoadWorkcellSimulation(testing::Source(kSimulation), testing::Plugins());
  *recording = SimulateWorkcell(spec, nullptr);
  std::string job = testing::ReadText(testing::Source(kJob));
  job = testing::ReplaceOnce(job, "../robots/ur3_vsb2020.yaml",
                             testing::Source("configs/robots/ur3_vsb2020.yaml"));
  if (!from.empty()) job = testing::ReplaceOnce(job, from, to);
  testing::WriteText(dir + "/job.yaml", job);
}

TEST(EyeInHand, WhatTheSettingDoesNotAllowIsRefusedInWords) {
  const std::string dir = testing::TempDirForThisTest("eye_in_hand");
  Recording recording;
  // The per-frame model needs a world pose per capture, which a moving camera has not.
  WriteCell(dir, "robots:", "camera_model: per_frame\nrobots:", &recording);
  const WorkcellJob per_frame =
      LoadWorkcellJob(dir + "/job.yaml", testing::Plugins(), /*recording_must_exist=*/false);
  const InputError e = testing::CatchInputError([&] { testing::Identify(per_frame, recording); });
  EXPECT_NE(e.message().find("eye in hand"), std::string::npos) << e.message();
  EXPECT_FALSE(e.hint().empty());
  // A camera the recording does not put on this robot.
  WriteCell(dir, "wrist: {free: all}", "elbow: {free: all}", &recording);
  const WorkcellJob elbow =
      LoadWorkcellJob(dir + "/job.yaml", testing::Plugins(), /*recording_must_exist=*/false);
  const InputError not_mounted =
      testing::CatchInputError([&] { ValidateJobAgainstRecording(elbow, recording); });
  EXPECT_NE(not_mounted.message().find("camera 'elbow' does not ride on robot 'ur3'"),
            std::string::npos)
      << not_mounted.message();
  EXPECT_GT(not_mounted.where().line, 0);
}

TEST(EyeInHand, ACameraOnAnUnknownRobotIsRefusedAtItsLine) {
  const std::string dir = testing::TempDirForThisTest("eye_in_hand");
  const WorkcellSimulationSpec spec =
      LoadWorkcellSimulation(testing::Source(kSimulation), testing::Plugins());
  WriteRecording(SimulateWorkcell(spec, nullptr), dir + "/rec");
  EXPECT_NE(testing::ReadText(dir + "/rec/recording.yaml").find("{name: wrist, on: ur3}"),
            std::string::npos);
  EXPECT_EQ(ReadRecording(dir + "/rec").camera_mounts.at("wrist"), "ur3");
  std::string text = testing::ReadText(dir + "/rec/recording.yaml");
  testing::WriteText(dir + "/rec/recording.yaml",
                     testing::ReplaceOnce(text, "on: ur3}", "on: ur5}"));
  const InputError e = testing::CatchInputError([&] { ReadRecording(dir + "/rec"); });
  EXPECT_NE(e.message().find("camera 'wrist' is on unknown robot 'ur5'"), std::string::npos)
      << e.message();
  EXPECT_NE(e.where().file.find("recording.yaml"), std::string::npos);
  EXPECT_GT(e.where().line, 0);
  EXPECT_NE(e.hint().find("robots"), std::string::npos);
}

}  // namespace
}  // namespace cellmetry
