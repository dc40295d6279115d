// Stereo triangulation with covariance, against truth and against Monte Carlo.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/imaging/stereo.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

StereoRig DistortedRig() {
  StereoRig rig = OakDLikeRig();
  rig.left.distortion = {-0.05, 0.01, 0.0004, -0.0002, 0.0};
  rig.right.distortion = {-0.04, 0.008, -0.0003, 0.0001, 0.0};
  const Eigen::Vector3d rvec(0.002, -0.004, 0.001);
  rig.T_right_left.R = RotationFromRvec(rvec.data());
  return rig;
}

Keypoint Seen(const PinholeCamera& camera, const Eigen::Vector3d& p, double sigma_px) {
  Keypoint k;
  k.pixel = camera.Project(p);
  k.covariance_px2 = Eigen::Matrix2d::Identity() * sigma_px * sigma_px;
  return k;
}

TEST(Triangulate, NoiseFreePointsComeBackExactly) {
  const StereoRig rig = DistortedRig();
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(150 * u(rng), 100 * u(rng), 450 + 150 * u(rng));
    const auto t =
        Triangulate(rig, Seen(rig.left, p, 0.1), Seen(rig.right, rig.T_right_left * p, 0.1));
    ASSERT_TRUE(t.has_value());
    EXPECT_LT((t->p_left_mm - p).norm(), 1e-9);
  }
}

// The reported covariance matches the scatter of noisy triangulations, and depth grows as
// Z^2 sigma_disparity / (f b).
TEST(Triangulate, CovarianceMatchesMonteCarloAndTheDepthFormula) {
  const StereoRig rig = OakDLikeRig();
  const double sigma_px = 0.1;
  for (double z : {300.0, 600.0}) {
    const Eigen::Vector3d p(20.0, -10.0, z);
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, sigma_px);
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d predicted = Eigen::Matrix3d::Zero();
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      Keypoint l = Seen(rig.left, p, sigma_px), r = Seen(rig.right, rig.T_right_left * p, sigma_px);
      l.pixel += Eigen::Vector2d(noise(rng), noise(rng));
      r.pixel += Eigen::Vector2d(noise(rng), noise(rng));
      const auto t = Triangulate(rig, l, r);
      ASSERT_TRUE(t.has_value());
      const Eigen::Vector3d e = t->p_left_mm - p;
      scatter += e * e.transpose() / n;
      predicted = t->covariance_mm2;
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(std::sqrt(scatter(k, k)) / std::sqrt(predicted(k, k)), 1.0, 0.06)
          << "axis " << k << " z " << z;
    }
    const double depth_formula = z * z * std::sqrt(2.0) * sigma_px / (880.0 * 75.0);
    EXPECT_NEAR(std::sqrt(predicted(2, 2)) / depth_formula, 1.0, 0.02) << "z " << z;
  }
}

TEST(ReadStereoRig, OurYamlAndOpenCvStereoCalibrationAgree) {
  const std::string dir = testing::TempDirForThisTest("stereo");
  testing::WriteText(dir + "/ours.yaml",
                     "stereo:\n"
                     "  left: {width: 1280, height: 800, fx: 880, fy: 880, cx: 639.5, cy: 399.5}\n"
                     "  right: {width: 1280, height: 800, fx: 881, fy: 881, cx: 640.5, cy: 400.5,"
                     " distortion: [0.01, 0, 0, 0, 0]}\n"
                     "  T_right_left: {xyz: [-75, 0.1, 0.2], rvec: [0, 0, 0]}\n");
  testing::WriteText(
      dir + "/opencv.yml",
      "%YAML:1.0\n---\nimage_width: 1280\nimage_height: 800\n"
      "M1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
      "   data: [ 880., 0., 639.5, 0., 880., 399.5, 0., 0., 1. ]\n"
      "D1: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0., 0., 0., 0., 0. ]\n"
      "M2: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
      "   data: [ 881., 0., 640.5, 0., 881., 400.5, 0., 0., 1. ]\n"
      "D2: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0.01, 0., 0., 0., 0. ]\n"
      "R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
      "   data: [ 1., 0., 0., 0., 1., 0., 0., 0., 1. ]\n"
      "T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ -75., 0.1, 0.2 ]\n");
  const StereoRig a = ReadStereoRig(dir + "/ours.yaml"), b = ReadStereoRig(dir + "/opencv.yml");
  EXPECT_DOUBLE_EQ(a.right.fx, b.right.fx);
  EXPECT_EQ(a.right.distortion, b.right.distortion);
  EXPECT_TRUE(a.T_right_left.t.isApprox(b.T_right_left.t));
  testing::WriteText(dir + "/broken.yml", "%YAML:1.0\n---\nimage_width: 1280\nimage_height: 800\n");
  EXPECT_THAT(testing::CatchInputError([&] { ReadStereoRig(dir + "/broken.yml"); }).what(),
              HasSubstr("missing field 'M1'"));
}

}  // namespace
}  // namespace cellmetry
