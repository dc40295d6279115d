// EstimateTargetPose (PnP) and what the workcell makes of detected poses (the noise model).
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/estimation/noise_model.h"
#include "cellmetry/imaging/render.h"
#include "cellmetry/imaging/target_pose.h"

namespace cellmetry {
namespace {

PinholeCamera Camera() {
  PinholeCamera c;
  c.width = 1280, c.height = 720;
  c.fx = c.fy = 900, c.cx = 639.5, c.cy = 359.5;
  c.distortion = {-0.08, 0.05, 0, 0, 0};
  return c;
}

// One tag's corners on the +z face of a 70 mm cube (z = 35 mm, not the target's z = 0 plane).
std::vector<MarkerPoint> CubeTopFace() {
  return {{0, {-25, -25, 35}}, {1, {25, -25, 35}}, {2, {25, 25, 35}}, {3, {-25, 25, 35}}};
}

Pose CubeInCamera() {
  const Eigen::Vector3d rvec(0.3, -0.2, 2.0);
  return PoseFromRvecT(rvec, Eigen::Vector3d(40, -30, 800));
}

std::vector<Keypoint> Seen(const std::vector<MarkerPoint>& layout, double sigma_px) {
  std::vector<Keypoint> keypoints = ProjectLayout(Camera(), CubeInCamera(), layout);
  for (auto& k : keypoints) k.covariance_px2 = Eigen::Matrix2d::Identity() * sigma_px * sigma_px;
  return keypoints;
}

TEST(TargetPose, OneCoplanarFaceOffTheTargetPlaneGivesTheExactPose) {
  const auto pose = EstimateTargetPose(Camera(), Seen(CubeTopFace(), 0.1), CubeTopFace());
  ASSERT_TRUE(pose.has_value());
  EXPECT_LT((pose->T_cam_target.t - CubeInCamera().t).norm(), 1e-6);
  EXPECT_LT(RotationError<double>(pose->T_cam_target.R, CubeInCamera().R).norm(), 1e-9);
  EXPECT_EQ(pose->rejected, 0);
  EXPECT_DOUBLE_EQ(pose->variance_factor, 1.0);
}

TEST(TargetPose, AHiddenCornerIsDroppedAndThePoseStaysRight) {
  std::vector<MarkerPoint> layout = CubeTopFace();
  for (const auto& p :
       std::vector<MarkerPoint>{{4, {-35, -20, 10}}, {5, {-35, 20, 10}}, {6, {-35, 20, -20}}}) {
    layout.push_back(p);  // three corners on the -x face too
  }
  std::vector<Keypoint> keypoints = Seen(layout, 0.1);
  keypoints[1].pixel += Eigen::Vector2d(3.0, -2.0);  // a corner of a tag half hidden by the arm
  const auto pose = EstimateTargetPose(Camera(), keypoints, layout);
  ASSERT_TRUE(pose.has_value());
  EXPECT_EQ(pose->rejected, 1);
  EXPECT_EQ(pose->points, 6);
  EXPECT_LT((pose->T_cam_target.t - CubeInCamera().t).norm(), 1e-6);
}

TEST(TargetPose, CovarianceGrowsWhenKeypointsAreNoisierThanClaimed) {
  std::vector<MarkerPoint> layout;
  for (int i = 0; i < 16; ++i) layout.push_back({i, {(i % 4) * 20.0, (i / 4) * 20.0, 0}});
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.5);  // 0.5 px, claimed 0.1 px
  std::vector<Keypoint> keypoints = Seen(layout, 0.1);
  for (auto& k : keypoints) k.pixel += Eigen::Vector2d(noise(rng), noise(rng));
  PoseEstimationOptions keep_all;
  keep_all.outlier_chi2 = 1e9;
  const auto pose = EstimateTargetPose(Camera(), keypoints, layout, keep_all);
  ASSERT_TRUE(pose.has_value());
  EXPECT_GT(pose->variance_factor, 10.0);  // ~ (0.5 / 0.1)^2 = 25
  EXPECT_LT(pose->variance_factor, 60.0);
}

// Detected poses carry covariances: the noise model uses them, and counts the captures of a
// world-fixed target (one view, repeated) as one.
TEST(NoiseModel, DetectedCovariancesGiveSigmaAndRepeatedWorldViewsCountOnce) {
  Recording recording;
  recording.robots["ur3"] = 6;
  recording.cameras = {"cam1"};
  recording.targets = {{"world", kWorldCarrier}, {"tool", "ur3"}};
  for (int i = 0; i < 25; ++i) {
    Sample sample;
    sample.id = sample.pose = i;
    sample.robot = "ur3";
    sample.q.assign(6, 0.0);
    recording.samples.push_back(sample);
    for (const std::string target : {"world", "tool"}) {
      Observation o;
      o.sample = i;
      o.camera = "cam1";
      o.target = target;
      o.rvec = Eigen::Vector3d::Zero();
      o.covariance_mm2 = Eigen::Vector3d(0.01, 0.04, 0.25).asDiagonal();
      o.rotation_covariance_rad2 = Eigen::Matrix3d::Identity() * 1e-8;
      recording.observations.push_back(o);
    }
  }
  const NoiseModel model = BuildNoiseModel(recording, NoiseSpec{});
  const TargetNoise& tool = model.at("cam1", "tool");
  EXPECT_TRUE(tool.position_mm.isApprox(Eigen::Vector3d(0.1, 0.2, 0.5)));
  EXPECT_NEAR(tool.rotation_rad.x(), 1e-4, 1e-12);
  const TargetNoise& world = model.at("cam1", "world");
  EXPECT_TRUE(world.position_mm.isApprox(Eigen::Vector3d(0.5, 1.0, 2.5)));  // x sqrt(25)
  EXPECT_NE(world.source.find("one view repeated"), std::string::npos);
}

}  // namespace
}  // namespace cellmetry
