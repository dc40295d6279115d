// The closed-form start's base fit in sums (core/cell/src/base_fit_sums.h) against the rigid fit
// it replaces, FitRigidTransform of the flange-side points onto the world points: the same pose
// for any tool translations, from sums taken once, and no pose where the points span no plane.
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/basics/rigid_fit.h"
#include "cellmetry/basics/transform.h"
#include "base_fit_sums.h"

namespace cellmetry {
namespace {

Pose RandomPose(std::mt19937& rng, double reach_mm) {
  std::uniform_real_distribution<double> t(-reach_mm, reach_mm), r(-1.5, 1.5);
  const double rvec[3] = {r(rng), r(rng), r(rng)};
  Pose pose;
  pose.R = RotationFromRvec(rvec);
  pose.t = Eigen::Vector3d(t(rng), t(rng), t(rng));
  return pose;
}

// 60 flange poses, two tools taking turns, world points the flange-side points moved by a base
// pose plus 0.5 mm of noise (so the fit is a compromise, not an exact match). With `repeats`,
// each flange pose is measured that many times in a row, each with its own noise (a pose's
// repeated captures).
std::vector<RobotPoint> Points(std::mt19937& rng, const std::vector<Eigen::Vector3d>& tool_t,
                               int repeats = 1) {
  const Pose T_world_base = RandomPose(rng, 800.0);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::vector<RobotPoint> points;
  Pose T_base_flange;
  for (int i = 0; i < 60 * repeats; ++i) {
    RobotPoint p;
    if (i % repeats == 0) T_base_flange = RandomPose(rng, 400.0);
    p.T_base_flange = T_base_flange;
    p.tool = (i / repeats) % 2;
    p.p_world = T_world_base * (p.T_base_flange * tool_t[p.tool]) +
                Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    p.R_world_target = Eigen::Matrix3d::Identity();
    points.push_back(p);
  }
  return points;
}

std::optional<Pose> ByRigidFit(const std::vector<RobotPoint>& points,
                               const std::vector<Eigen::Vector3d>& tool_t) {
  std::vector<Eigen::Vector3d> flange_side, world;
  for (const RobotPoint& p : points) {
    flange_side.push_back(p.T_base_flange * tool_t[p.tool]);
    world.push_back(p.p_world);
  }
  return FitRigidTransform(flange_side, world);
}

// The sums' fit against the rigid fit of `points` at the truth (two tools) and at nine random
// tool translations: the alternation asks at translations far from and near the truth.
void ExpectTheRigidFit(const std::vector<RobotPoint>& points,
                       const std::vector<Eigen::Vector3d>& truth, std::mt19937& rng) {
  const BaseFitSums sums(points, 2);
  std::uniform_real_distribution<double> t(-150.0, 150.0);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<Eigen::Vector3d> tool_t = {{t(rng), t(rng), t(rng)}, {t(rng), t(rng), t(rng)}};
    if (trial == 0) tool_t = truth;
    const std::optional<Pose> expected = ByRigidFit(points, tool_t);
    const std::optional<Pose> fitted = sums.Fit(tool_t);
    ASSERT_TRUE(expected.has_value());
    ASSERT_TRUE(fitted.has_value()) << "trial " << trial;
    EXPECT_LT((fitted->R - expected->R).norm(), 1e-9) << "trial " << trial;
    EXPECT_LT((fitted->t - expected->t).norm(), 1e-6) << "trial " << trial << " (mm)";
  }
}

TEST(BaseFitSums, IsTheRigidFitForAnyToolTranslation) {
  std::mt19937 rng(7);
  const std::vector<Eigen::Vector3d> truth = {{10, -20, 66}, {-30, 5, 120}};
  ExpectTheRigidFit(Points(rng, truth), truth, rng);
}

// A pose's repeated captures: summed once per run of equal flange poses, the fit is still the
// rigid fit of every point.
TEST(BaseFitSums, RepeatedFlangePosesAreSummedAsTheirPoints) {
  std::mt19937 rng(5);
  const std::vector<Eigen::Vector3d> truth = {{10, -20, 66}, {-30, 5, 120}};
  const std::vector<RobotPoint> points = Points(rng, truth, /*repeats=*/3);
  const std::vector<size_t> starts = FlangeRunStarts(points);
  ASSERT_EQ(starts.size(), 61u);  // 60 runs of 3, then the end
  EXPECT_EQ(starts[1], 3u);
  EXPECT_EQ(starts.back(), points.size());
  ExpectTheRigidFit(points, truth, rng);
}

TEST(BaseFitSums, NoPoseWhereThePointsSpanNoPlane) {
  std::mt19937 rng(11);
  const std::vector<Eigen::Vector3d> tool_t = {{0, 0, 50}, {0, 0, 50}};
  std::vector<RobotPoint> points = Points(rng, tool_t);
  // Every world point on one line: the rotation about it is free.
  for (size_t i = 0; i < points.size(); ++i) {
    points[i].p_world = Eigen::Vector3d(1.0, 2.0, 3.0) * static_cast<double>(i);
  }
  EXPECT_FALSE(BaseFitSums(points, 2).Fit(tool_t).has_value());
  // Fewer than three points.
  points.resize(2);
  EXPECT_FALSE(BaseFitSums(points, 2).Fit(tool_t).has_value());
  // Flange-side points on one line: one pure translation of the flange along z, one tool at
  // the flange's origin.
  std::vector<RobotPoint> on_a_line = Points(rng, tool_t);
  for (size_t i = 0; i < on_a_line.size(); ++i) {
    on_a_line[i].T_base_flange.R = Eigen::Matrix3d::Identity();
    on_a_line[i].T_base_flange.t = Eigen::Vector3d(0.0, 0.0, 10.0 * static_cast<double>(i));
  }
  const std::vector<Eigen::Vector3d> at_origin = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  EXPECT_FALSE(BaseFitSums(on_a_line, 2).Fit(at_origin).has_value());
  EXPECT_FALSE(ByRigidFit(on_a_line, at_origin).has_value());
}

}  // namespace
}  // namespace cellmetry
