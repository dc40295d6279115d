// Transforms, rotation helpers and the closed-form rigid fit.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/basics/rigid_fit.h"
#include "cellmetry/basics/transform.h"
#include "cellmetry/model/frame_block.h"

namespace cellmetry {
namespace {

Pose RandomPose(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d rvec(n(rng), n(rng), n(rng));
  return PoseFromRvecT(rvec, Eigen::Vector3d(100 * n(rng), 100 * n(rng), 100 * n(rng)));
}

TEST(Transform, ComposeAndInverseFollowTheFrameConvention) {
  std::mt19937 rng(1);
  const Pose T_a_b = RandomPose(rng), T_b_c = RandomPose(rng);
  const Eigen::Vector3d p_c(1, 2, 3);
  EXPECT_TRUE(((T_a_b * T_b_c) * p_c).isApprox(T_a_b * (T_b_c * p_c), 1e-12));
  const Pose identity = T_a_b * T_a_b.inverse();
  EXPECT_TRUE(identity.R.isIdentity(1e-12));
  EXPECT_LT(identity.t.norm(), 1e-12);
}

TEST(Transform, RvecRoundTripsUpToPi) {
  for (double angle : {1e-9, 0.3, 2.0, 3.1}) {
    const Eigen::Vector3d rvec = Eigen::Vector3d(1, -2, 0.5).normalized() * angle;
    EXPECT_TRUE(RvecFromRotation(RotationFromRvec(rvec.data())).isApprox(rvec, 1e-9)) << angle;
  }
}

TEST(Transform, MeanRotationOfSymmetricSpreadIsTheCentre) {
  const Eigen::Matrix3d centre = RotationFromRvec(Eigen::Vector3d(0.2, 0.1, -0.3).eval().data());
  std::vector<Eigen::Matrix3d> rotations;
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {-1.0, 1.0}) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[axis] = 0.01 * sign;
      rotations.push_back(RotationFromRvec(d.data()) * centre);
    }
  }
  EXPECT_LT(RotationError<double>(MeanRotation(rotations), centre).norm(), 1e-12);
}

TEST(RigidFit, RecoversAKnownTransformExactly) {
  std::mt19937 rng(2);
  const Pose truth = RandomPose(rng);
  std::vector<Eigen::Vector3d> from, to;
  std::normal_distribution<double> n(0.0, 300.0);
  for (int i = 0; i < 10; ++i) {
    from.emplace_back(n(rng), n(rng), n(rng));
    to.push_back(truth * from.back());
  }
  const auto fit = FitRigidTransform(from, to);
  ASSERT_TRUE(fit);
  EXPECT_LT(RotationError<double>(fit->R, truth.R).norm(), 1e-12);
  EXPECT_LT((fit->t - truth.t).norm(), 1e-9);
}

TEST(RigidFit, RefusesCollinearPoints) {
  std::vector<Eigen::Vector3d> from = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  EXPECT_FALSE(FitRigidTransform(from, from));
  EXPECT_FALSE(FitRigidTransform({{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}}));
}

TEST(FrameBlock, ParametersAreACorrectionAroundTheStartRotation) {
  const Pose start = PoseFromRvecT(Eigen::Vector3d(0.5, -1.0, 2.0), Eigen::Vector3d(1, 2, 3));
  FrameBlockSpec spec;
  spec.start = start;
  const auto params = FrameParameters(spec);
  std::vector<double> block;
  for (const auto& p : params) block.push_back(p.nominal);
  const Pose at_start = FrameFromBlock(block.data(), start.R);
  EXPECT_TRUE(at_start.R.isApprox(start.R, 1e-15));
  EXPECT_TRUE(at_start.t.isApprox(start.t, 1e-15));
  EXPECT_EQ(params[3].unit, "rad");
  EXPECT_EQ(params[0].unit, "mm");
}

// The point maps the Jet residuals use agree with the frame they stand for, in value and in
// derivative (Jets against the matrix form), at a small and a large correction.
TEST(FrameBlock, PointMapsAgreeWithTheFrameInValueAndDerivative) {
  using J = ceres::Jet<double, 6>;
  const Eigen::Matrix3d R_ref = RotationFromRvec(Eigen::Vector3d(0.4, -1.2, 2.1).data());
  const Eigen::Vector3d p(120.0, -35.0, 410.0);
  for (double size : {1e-4, 0.3}) {
    J block[6];
    const double values[6] = {5.0, -3.0, 700.0, size, -2 * size, 0.5 * size};
    for (int i = 0; i < 6; ++i) block[i] = J(values[i], i);
    const Transform<J> frame = FrameFromBlock(block, R_ref);
    const Vector3<J> p_jet = p.cast<J>();
    const Vector3<J> mapped = FrameBlockMap(block, R_ref, p_jet);
    const Vector3<J> expected = frame.R * p_jet + frame.t;
    const Vector3<J> back = FrameBlockInverseMap(block, R_ref, p_jet);
    const Vector3<J> expected_back = frame.R.transpose() * (p_jet - frame.t);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(mapped[i].a, expected[i].a, 1e-10);
      EXPECT_NEAR(back[i].a, expected_back[i].a, 1e-10);
      EXPECT_TRUE(mapped[i].v.isApprox(expected[i].v, 1e-10)) << mapped[i].v.transpose();
      EXPECT_TRUE(back[i].v.isApprox(expected_back[i].v, 1e-10)) << back[i].v.transpose();
    }
  }
}

}  // namespace
}  // namespace cellmetry
