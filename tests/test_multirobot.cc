// Multi-robot cells: the robot-to-robot transform T_robotA_robotB and its sigma from
// both bases' joint covariance; tool names shared by two robots refused.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cellmetry/basics/relative_pose.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/result_io.h"
#include "cellmetry/cell/robot_pairs.h"
#include "cellmetry/cell/truth.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/exports/tf_export.h"
#include "cellmetry/model/frame_block.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

// (dt, dphi) of `T` from `reference`, the rotation about the parent's axes: R = Exp(dphi) R_ref.
Eigen::Matrix<double, 6, 1> Difference(const Pose& T, const Pose& reference) {
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>() = T.t - reference.t;
  d.tail<3>() = RvecFromRotation(T.R * reference.R.transpose());
  return d;
}

// The propagation's Jacobian against central differences, perturbing both bases the way the
// frame blocks do (R = Exp(r) R_ref, t absolute; frame_block.h) and reading T_a_b's error the way
// its sigma is stated (about a's axes).
TEST(RobotToRobot, JacobianMatchesCentralDifferences) {
  const Pose a = PoseFromRvecT({0.1, -0.3, 1.2}, {-350, 150, -455});
  const Pose b = PoseFromRvecT({-0.2, 0.05, 0.4}, {431, 555, -460});
  const Eigen::Matrix<double, 6, 12> J = RelativePoseJacobian(a, b);
  const Pose T_ab = a.inverse() * b;
  for (int k = 0; k < 12; ++k) {
    const double h = k % 6 < 3 ? 1e-3 : 1e-6;
    auto moved = [&](double step) {
      double block_a[6] = {a.t.x(), a.t.y(), a.t.z(), 0, 0, 0};
      double block_b[6] = {b.t.x(), b.t.y(), b.t.z(), 0, 0, 0};
      (k < 6 ? block_a : block_b)[k % 6] += step;
      const Pose pa = FrameFromBlock(block_a, a.R);
      const Pose pb = FrameFromBlock(block_b, b.R);
      return Difference(pa.inverse() * pb, T_ab);
    };
    const Eigen::Matrix<double, 6, 1> numeric = (moved(h) - moved(-h)) / (2 * h);
    for (int i = 0; i < 6; ++i) {
      EXPECT_NEAR(J(i, k), numeric[i], 1e-6 * std::max(1.0, std::abs(numeric[i])))
          << "d(row " << i << ")/d(column " << k << ")";
    }
  }
}

// The joint covariance, not the sum of variances: two bases found through the same cameras
// share the cameras' errors, and T_a_b's sigma is what is left once they cancel.
TEST(RobotToRobot, UsesTheCrossCovariance) {
  const Pose a = PoseFromRvecT({0, 0, 1.2}, {-350, 150, -455});
  const Pose b = PoseFromRvecT({0, 0, 0}, {431, 555, -460});
  // Translations only (rotations known exactly): each base 1e-4 mm^2 per axis.
  Eigen::Matrix<double, 12, 12> shared = Eigen::Matrix<double, 12, 12>::Zero();
  for (int i : {0, 1, 2, 6, 7, 8}) shared(i, i) = 1e-4;
  Eigen::Matrix<double, 12, 12> independent = shared;
  for (int i = 0; i < 3; ++i) shared(i, 6 + i) = shared(6 + i, i) = 0.9e-4;  // dt_a ~ dt_b
  const RelativePose with = PoseInFrame(a, b, shared);
  const RelativePose without = PoseInFrame(a, b, independent);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(with.covariance(i, i), 0.2e-4, 1e-12);  // 2 (1 - 0.9) 1e-4
    EXPECT_NEAR(without.covariance(i, i), 2e-4, 1e-12);
  }
}

struct Figures {
  double coverage3 = 0;         // fraction of components within 3 sigma
  double mean_mahalanobis = 0;  // e^T C^-1 e, mean over seeds (6 expected)
  Eigen::Matrix<double, 6, 1> spread, mean_sigma, sum_sigma;  // spread over seeds; sigma
  Eigen::Matrix<double, 6, 1> model_sigma;  // from the model covariance alone (no robust or
                                            // systematic parts), for the figures
};

// configs/simulations/ur5e_ur3_cell.yaml with 20 noise seeds (same truth, same poses),
// identified by configs/jobs/ur5e_ur3_cell.yaml (cross-validation off: not what is tested).
// With 100 seeds (kSeeds = 100, 8 s) the spread / sigma ratios were 0.85-0.98 per component,
// 600 of 600 within 3 sigma, mean Mahalanobis^2 5.44; the model-only sigma matched the spread
// within 5 % (y: 5 % above it): the total sigma's robust and systematic parts, scaled with the
// model's correlation, make it 5-15 % conservative here.
TEST(RobotToRobot, WithinThreeSigmaAndSigmaMatchesTheSpreadOver20Seeds) {
  WorkcellSimulationSpec sim = LoadWorkcellSimulation(
      testing::Source("configs/simulations/ur5e_ur3_cell.yaml"), testing::Plugins());
  WorkcellJob job = LoadWorkcellJob(testing::Source("configs/jobs/ur5e_ur3_cell.yaml"),
                                    testing::Plugins(), false);
  job.problem.folds = 0;
  const Pose truth = sim.robots[0].T_world_base.inverse() * sim.robots[1].T_world_base;
  constexpr int kSeeds = 20;
  std::vector<Eigen::Matrix<double, 6, 1>> errors;
  Figures f;
  f.mean_sigma.setZero();
  f.sum_sigma.setZero();
  f.model_sigma.setZero();
  int within = 0, exceed = 0;
  for (int seed = 0; seed < kSeeds; ++seed) {
    sim.noise_seed = 1000 + seed;
    const Recording recording = SimulateWorkcell(sim, nullptr);
    const WorkcellResult result = testing::Identify(job, recording);
    ASSERT_EQ(result.robot_to_robot.size(), 2u);  // ur3 in ur5e, ur5e in ur3
    const RobotPairEstimate& pair = result.robot_to_robot[0];
    ASSERT_EQ(pair.frame.name, "ur3.base");
    ASSERT_EQ(pair.frame.parent, "ur5e.base");
    const Eigen::Matrix<double, 6, 1> e = Difference(pair.frame.pose, truth);
    Eigen::Matrix<double, 6, 1> sigma;
    sigma << pair.frame.sigma_mm, pair.frame.sigma_rad;
    for (int i = 0; i < 6; ++i) (std::abs(e[i]) < 3 * sigma[i] ? within : exceed)++;
    f.mean_mahalanobis += e.dot(pair.covariance.ldlt().solve(e)) / kSeeds;
    f.mean_sigma += sigma / kSeeds;
    // What adding the two bases' sigmas (no cross-covariance) would say, for the figures.
    const Eigen::Matrix<double, 6, 1> sa =
        (Eigen::Matrix<double, 6, 1>() << testing::Frame(result, "ur5e.base").sigma_mm,
         testing::Frame(result, "ur5e.base").sigma_rad)
            .finished();
    const Eigen::Matrix<double, 6, 1> sb =
        (Eigen::Matrix<double, 6, 1>() << testing::Frame(result, "ur3.base").sigma_mm,
         testing::Frame(result, "ur3.base").sigma_rad)
            .finished();
    f.sum_sigma += (sa.cwiseAbs2() + sb.cwiseAbs2()).cwiseSqrt() / kSeeds;
    Uncertainty model_only = result.uncertainty;
    model_only.correlation.resize(0, 0);  // FramePairCovariance then reads the covariance itself
    const RelativePose by_model = PoseInFrame(
        testing::Frame(result, "ur5e.base").pose, testing::Frame(result, "ur3.base").pose,
        FramePairCovariance(model_only, "ur5e.base", "ur3.base"));
    f.model_sigma += by_model.covariance.diagonal().cwiseSqrt() / kSeeds;
    errors.push_back(e);
  }
  Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero();
  for (const auto& e : errors) mean += e / kSeeds;
  f.spread.setZero();
  for (const auto& e : errors) f.spread += (e - mean).cwiseAbs2() / (kSeeds - 1);
  f.spread = f.spread.cwiseSqrt();
  f.coverage3 = static_cast<double>(within) / (within + exceed);
  std::printf("T_ur5e_ur3 over %d seeds (x y z mm, rx ry rz rad):\n", kSeeds);
  for (int i = 0; i < 6; ++i) {
    std::printf(
        "  %s: spread %.3g, mean sigma %.3g (ratio %.2f), model-only sigma %.3g, bases' "
        "sigmas added %.3g\n",
        kFrameParameterNames[i].c_str(), f.spread[i], f.mean_sigma[i],
        f.spread[i] / f.mean_sigma[i], f.model_sigma[i], f.sum_sigma[i]);
  }
  std::printf("  within 3 sigma: %d of %d components; mean Mahalanobis^2 %.2f (6 expected)\n",
              within, within + exceed, f.mean_mahalanobis);
  // 120 components: a true sigma leaves 0.3 of them beyond 3 sigma on average; one is allowed.
  EXPECT_LE(exceed, 1);
  // The spread of 20 draws has a relative standard error of 1/sqrt(2 * 19) = 16 %: sigma must
  // match it within [0.6, 1.5] (about 2.5 standard errors) in every component.
  for (int i = 0; i < 6; ++i) {
    EXPECT_GT(f.spread[i] / f.mean_sigma[i], 0.6) << kFrameParameterNames[i];
    EXPECT_LT(f.spread[i] / f.mean_sigma[i], 1.5) << kFrameParameterNames[i];
  }
  // The chi-square of 6 has mean 6 and, averaged over 20 draws, a standard error of 0.77.
  EXPECT_GT(f.mean_mahalanobis, 6 - 3 * 0.77);
  EXPECT_LT(f.mean_mahalanobis, 6 + 3 * 0.77);
}

// result.yaml, result.json and the summary carry T_ur5e_ur3 with its sigma.
TEST(RobotToRobot, WrittenInEveryResultFile) {
  WorkcellSimulationSpec sim = LoadWorkcellSimulation(
      testing::Source("configs/simulations/ur5e_ur3_cell.yaml"), testing::Plugins());
  WorkcellJob job = LoadWorkcellJob(testing::Source("configs/jobs/ur5e_ur3_cell.yaml"),
                                    testing::Plugins(), false);
  job.problem.folds = 0;
  const WorkcellResult result = testing::Identify(job, SimulateWorkcell(sim, nullptr));
  EXPECT_THAT(WorkcellResultYaml(result),
              HasSubstr("robot_to_robot:\n  T_ur5e_ur3:\n    parent: ur5e.base"));
  const nlohmann::json j = WorkcellResultJson(result);
  ASSERT_TRUE(j["robot_to_robot"].contains("T_ur5e_ur3"));
  ASSERT_TRUE(j["robot_to_robot"].contains("T_ur3_ur5e"));
  EXPECT_EQ(j["robot_to_robot"]["T_ur5e_ur3"]["sigma_xyz_mm"].size(), 3u);
  EXPECT_EQ(j["robot_to_robot"]["T_ur5e_ur3"]["covariance"].size(), 6u);
  EXPECT_THAT(WorkcellSummary(result), HasSubstr("ur3.base in ur5e.base: xyz = ("));
  // `cellmetry evaluate` scores it against the truth's two bases, in its own sigma.
  WorkcellTruth truth;
  SimulateWorkcell(sim, &truth);
  int scored = 0;
  for (const auto& q : EvaluateWorkcell(j, truth, "truth").quantities) {
    if (q.name.rfind("T_ur5e_ur3.", 0) != 0) continue;
    ++scored;
    EXPECT_LT(std::abs(q.normalized()), 3.0) << q.name;
  }
  EXPECT_EQ(scored, 6);
  for (const auto& q : EvaluateWorkcell(j, truth, "truth").quantities) {
    if (q.name.rfind("T_ur3_ur5e.", 0) == 0) {
      EXPECT_LT(std::abs(q.normalized()), 3.0) << q.name;
    }
  }
}

// One propagation, two readers: the tf export's robot-to-robot comment (from result.json) says
// the sigma the result's robot_to_robot says.
TEST(RobotToRobot, TheTfExportSaysTheSameSigma) {
  WorkcellSimulationSpec sim = LoadWorkcellSimulation(
      testing::Source("configs/simulations/ur5e_ur3_cell.yaml"), testing::Plugins());
  WorkcellJob job = LoadWorkcellJob(testing::Source("configs/jobs/ur5e_ur3_cell.yaml"),
                                    testing::Plugins(), false);
  job.problem.folds = 0;
  const WorkcellResult result = testing::Identify(job, SimulateWorkcell(sim, nullptr));
  const std::string dir = testing::TempDirForThisTest("multirobot");
  WriteWorkcellResult(result, dir + "/result");
  const std::string tf = TfLaunchExport(ReadCalibratedCell(dir + "/result", testing::Plugins()));
  const FrameEstimate& f = result.robot_to_robot.at(0).frame;
  char sigma[96];
  std::snprintf(sigma, sizeof sigma, "sigma xyz (%.2g, %.2g, %.2g) mm, rot (%.2g, %.2g, %.2g) rad",
                f.sigma_mm.x(), f.sigma_mm.y(), f.sigma_mm.z(), f.sigma_rad.x(), f.sigma_rad.y(),
                f.sigma_rad.z());
  EXPECT_THAT(tf, HasSubstr(sigma));
}

// Two robots both naming their tool `gripper`: the recording would hold one target for two
// markers. Refused at the second key, in `simulate` and in `run`.
TEST(DuplicateToolNames, RefusedBySimulateAtTheSecondKey) {
  const std::string dir = testing::TempDirForThisTest("multirobot");
  std::string text = testing::ReadText(testing::Source("configs/simulations/ur5e_ur3_cell.yaml"));
  text = testing::ReplaceOnce(text, "      tool: {xyz: [0.5", "      gripper: {xyz: [0.5");
  text = testing::ReplaceOnce(text, "model: ../robots/ur5e.yaml",
                              "model: " + testing::Source("configs/robots/ur5e.yaml"));
  text = testing::ReplaceOnce(text, "model: ../robots/ur3_vsb2020.yaml",
                              "model: " + testing::Source("configs/robots/ur3_vsb2020.yaml"));
  testing::WriteText(dir + "/sim.yaml", text);
  const auto r = testing::RunCellmetry("simulate " + dir + "/sim.yaml -o " + dir + "/out");
  testing::ExpectOneLineError(
      r, "sim.yaml:26:7:", "target 'gripper' is already a tool of robot 'ur5e'");
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
}

}  // namespace
}  // namespace cellmetry
