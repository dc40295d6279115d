// The delta arm plugin: exact three-sphere forward kinematics, closed-form inverse kinematics,
// their agreement across the workspace, their derivatives, and their failures.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/model/robot_model.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

std::unique_ptr<RobotModel> LoadDelta() {
  return testing::Plugins().CreateRobotModel(
      "delta", ConfigNode::LoadFile(testing::Source("configs/robots/delta.yaml")));
}

// Nominal parameters with up to 1 mm / 0.01 rad of error, so that the three arms differ.
std::vector<double> PerturbedParameters(const RobotModel& model, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> mm(-1.0, 1.0), rad(-0.01, 0.01);
  std::vector<double> values;
  for (const auto& p : model.parameters())
    values.push_back(p.nominal + (p.unit == "mm" ? mm(rng) : rad(rng)));
  return values;
}

// Points on a grid through the configured workspace cylinder.
std::vector<Eigen::Vector3d> WorkspaceGrid(const RobotModel& model) {
  const CylinderWorkspace w = *model.limits().workspace;
  std::vector<Eigen::Vector3d> points;
  for (double z = w.z_min_mm; z <= w.z_max_mm + 1e-9; z += (w.z_max_mm - w.z_min_mm) / 4) {
    for (double x = -w.radius_mm; x <= w.radius_mm + 1e-9; x += w.radius_mm / 4) {
      for (double y = -w.radius_mm; y <= w.radius_mm + 1e-9; y += w.radius_mm / 4) {
        if (x * x + y * y <= w.radius_mm * w.radius_mm + 1e-9) points.emplace_back(x, y, z);
      }
    }
  }
  return points;
}

TEST(Delta, ConfigCarriesTheNominalArmResolutionAndWorkspace) {
  const auto model = LoadDelta();
  ASSERT_EQ(model->num_joints(), 3);
  ASSERT_EQ(model->parameters().size(), 15u);
  EXPECT_EQ(model->parameters()[0].name, "arm1.R");
  EXPECT_EQ(model->parameters()[14].name, "arm3.homing");
  EXPECT_DOUBLE_EQ(model->parameters()[3].nominal, 600.0);
  EXPECT_NEAR(model->limits().joint_increment_rad, 2 * M_PI / 10000, 1e-15);
  ASSERT_TRUE(model->limits().workspace.has_value());
  EXPECT_TRUE(model->has_inverse());
  EXPECT_DOUBLE_EQ(model->nominal_tool().t.z(), -60.0);
}

TEST(Delta, HomePoseOfTheNominalArmIsOnTheAxis) {
  const auto model = LoadDelta();
  std::vector<double> nominal;
  for (const auto& p : model->parameters()) nominal.push_back(p.nominal);
  const double q[3] = {0, 0, 0};
  Pose flange;
  ASSERT_TRUE(model->Forward(q, nominal.data(), &flange));
  // Elbows at radius R - r + L = 360 mm, z = 0; rods 600 mm: the effector at z = -480 mm.
  EXPECT_NEAR(flange.t.x(), 0.0, 1e-12);
  EXPECT_NEAR(flange.t.y(), 0.0, 1e-12);
  EXPECT_NEAR(flange.t.z(), -480.0, 1e-12);
  EXPECT_TRUE(flange.R.isIdentity(0));
}

TEST(Delta, InverseThenForwardIsIdentityAcrossTheWorkspace) {
  const auto model = LoadDelta();
  for (unsigned seed : {1u, 2u, 3u}) {
    const std::vector<double> params = PerturbedParameters(*model, seed);
    double worst_mm = 0.0, worst_rad = 0.0;
    for (const Eigen::Vector3d& p : WorkspaceGrid(*model)) {
      double q[3];
      ASSERT_TRUE(model->Inverse(p.data(), params.data(), q)) << p.transpose();
      Pose flange;
      ASSERT_TRUE(model->Forward(q, params.data(), &flange)) << p.transpose();
      worst_mm = std::max(worst_mm, (flange.t - p).norm());
      double q_again[3];
      ASSERT_TRUE(model->Inverse(flange.t.data(), params.data(), q_again));
      for (int i = 0; i < 3; ++i) worst_rad = std::max(worst_rad, std::abs(q_again[i] - q[i]));
    }
    EXPECT_LT(worst_mm, 1e-9) << "seed " << seed;
    EXPECT_LT(worst_rad, 1e-12) << "seed " << seed;
  }
}

TEST(Delta, ForwardMeetsEveryRodWithItsOwnLength) {
  // Distinct rods (598, 600, 603 mm): the report's formula, which averages them, would miss.
  const auto model = LoadDelta();
  std::vector<double> params;
  for (const auto& p : model->parameters()) params.push_back(p.nominal);
  params[3] = 598.0, params[8] = 600.0, params[13] = 603.0;
  const double q[3] = {0.3, 0.1, 0.5};
  Pose flange;
  ASSERT_TRUE(model->Forward(q, params.data(), &flange));
  for (int i = 0; i < 3; ++i) {
    const double alpha = 2 * M_PI * i / 3;
    const double* arm = params.data() + 5 * i;
    const double rho = arm[0] - arm[1] + arm[2] * std::cos(q[i] + arm[4]);
    const Eigen::Vector3d centre(rho * std::sin(alpha), -rho * std::cos(alpha),
                                 -arm[2] * std::sin(q[i] + arm[4]));
    EXPECT_NEAR((flange.t - centre).norm(), arm[3], 1e-9) << "arm " << i + 1;
  }
}

// d(output)/d(param) by Jets against central differences, for Forward and Inverse.
TEST(Delta, DerivativesMatchCentralDifferences) {
  const auto model = LoadDelta();
  const std::vector<double> params = PerturbedParameters(*model, 9);
  const int n = static_cast<int>(params.size());
  const double q[3] = {0.35, -0.1, 0.6};
  const Eigen::Vector3d point(40.0, -70.0, -600.0);
  const double h = 1e-6;
  for (int k = 0; k < n; ++k) {
    std::vector<Jet> jets(params.begin(), params.end());
    jets[k].v[0] = 1.0;
    Transform<Jet> flange_jet;
    ASSERT_TRUE(model->Forward(q, jets.data(), &flange_jet));
    Jet point_jet[3] = {Jet(point.x()), Jet(point.y()), Jet(point.z())}, q_jet[3];
    ASSERT_TRUE(model->Inverse(point_jet, jets.data(), q_jet));

    std::vector<double> plus = params, minus = params;
    plus[k] += h;
    minus[k] -= h;
    Pose fp, fm;
    ASSERT_TRUE(model->Forward(q, plus.data(), &fp));
    ASSERT_TRUE(model->Forward(q, minus.data(), &fm));
    double qp[3], qm[3];
    ASSERT_TRUE(model->Inverse(point.data(), plus.data(), qp));
    ASSERT_TRUE(model->Inverse(point.data(), minus.data(), qm));
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(flange_jet.t[i].v[0], (fp.t[i] - fm.t[i]) / (2 * h), 1e-6)
          << model->parameters()[k].name << " forward " << i;
      EXPECT_NEAR(q_jet[i].v[0], (qp[i] - qm[i]) / (2 * h), 1e-8)
          << model->parameters()[k].name << " inverse " << i;
    }
  }
}

TEST(Delta, InverseDerivativeWithRespectToThePointMatchesCentralDifferences) {
  const auto model = LoadDelta();
  const std::vector<double> params = PerturbedParameters(*model, 4);
  const std::vector<Jet> jets(params.begin(), params.end());
  const Eigen::Vector3d point(-90.0, 60.0, -560.0);
  for (int k = 0; k < 3; ++k) {
    Jet p[3] = {Jet(point.x()), Jet(point.y()), Jet(point.z())}, q[3];
    p[k].v[0] = 1.0;
    ASSERT_TRUE(model->Inverse(p, jets.data(), q));
    Eigen::Vector3d plus = point, minus = point;
    plus[k] += 1e-5;
    minus[k] -= 1e-5;
    double qp[3], qm[3];
    ASSERT_TRUE(model->Inverse(plus.data(), params.data(), qp));
    ASSERT_TRUE(model->Inverse(minus.data(), params.data(), qm));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(q[i].v[0], (qp[i] - qm[i]) / 2e-5, 1e-9);
  }
}

TEST(Delta, UnreachablePointSaysWhichArm) {
  const auto model = LoadDelta();
  std::vector<double> params;
  for (const auto& p : model->parameters()) params.push_back(p.nominal);
  const Eigen::Vector3d far(0.0, 0.0, -1200.0);
  double q[3];
  EXPECT_FALSE(model->Inverse(far.data(), params.data(), q));
  EXPECT_THAT(model->InverseFailure(far.data(), params.data()), HasSubstr("arm 1 cannot reach"));
}

TEST(Delta, SpheresThatDoNotMeetAreReported) {
  const auto model = LoadDelta();
  std::vector<double> params;
  for (const auto& p : model->parameters()) params.push_back(p.nominal);
  for (int i = 0; i < 3; ++i) params[5 * i + 3] = 300.0;  // rods shorter than the elbows' spread
  const double q[3] = {0, 0, 0};
  Pose flange;
  EXPECT_FALSE(model->Forward(q, params.data(), &flange));
  EXPECT_THAT(model->ForwardFailure(q, params.data()), HasSubstr("rod spheres do not meet"));
}

TEST(Delta, ConfigWithTwoArmsIsRejected) {
  const ConfigNode config = ConfigNode::LoadString(
      "type: delta\narms:\n  - {R: 150, r: 40, L: 250, l: 600}\n  - {R: 150, r: 40, L: 250, l: "
      "600}\n",
      "delta.yaml");
  const InputError e =
      testing::CatchInputError([&] { testing::Plugins().CreateRobotModel("delta", config); });
  EXPECT_THAT(e.what(), HasSubstr("a delta arm has 3 arms, this lists 2"));
}

}  // namespace
}  // namespace cellmetry
