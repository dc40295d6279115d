// The serial MDH plugin: the paper's UR3 table, exact derivatives, configuration errors.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cellmetry/formats/config_node.h"
#include "support/model_derivatives.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

std::unique_ptr<RobotModel> Ur3() {
  const ConfigNode config =
      ConfigNode::LoadFile(testing::Source("configs/robots/ur3_vsb2020.yaml"));
  return testing::Plugins().CreateRobotModel("serial_mdh", config);
}

std::vector<double> Nominal(const RobotModel& model) {
  std::vector<double> values;
  for (const auto& p : model.parameters()) values.push_back(p.nominal);
  return values;
}

TEST(SerialMdh, Ur3HomeMatchesTheHandComputedChain) {
  const auto model = Ur3();
  ASSERT_EQ(model->num_joints(), 6);
  ASSERT_EQ(model->parameters().size(), 30u);
  // All joints at zero, offsets pi on joints 2 and 6: the arm lies along -x0, so
  // x = -(a3 + a4), y = -(d2 + d4 + d6), z = d1 - d5 (checked independently with numpy).
  const std::vector<double> q(6, 0.0);
  Pose T;
  ASSERT_TRUE(model->Forward(q.data(), Nominal(*model).data(), &T));
  EXPECT_NEAR(T.t.x(), -456.90, 1e-9);
  EXPECT_NEAR(T.t.y(), -(119.85 - 9.45 + 81.90), 1e-9);
  EXPECT_NEAR(T.t.z(), 151.90 - 85.35, 1e-9);
  EXPECT_NEAR(T.R.determinant(), 1.0, 1e-12);
}

// Every parameter's derivative, from the Jet overload, against central differences.
TEST(SerialMdh, JetDerivativesMatchCentralDifferences) {
  const auto model = Ur3();
  const std::vector<double> nominal = Nominal(*model);
  const int n = static_cast<int>(nominal.size());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> q(6);
    for (double& v : q) v = angle(rng);
    for (int k = 0; k < n; ++k) {
      Transform<Jet> T_jet;
      ASSERT_TRUE(testing::JetByParameter(*model, q, nominal, k, &T_jet));
      const testing::CentralDifference d =
          testing::CentralDifferenceByParameter(*model, q, nominal, k);
      for (int r = 0; r < 3; ++r) {
        EXPECT_NEAR(T_jet.t[r].v[0], d.dt[r], 1e-6 * (1 + std::abs(d.dt[r])))
            << model->parameters()[k].name;
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(T_jet.R(r, c).v[0], d.dR(r, c), 1e-6) << model->parameters()[k].name;
        }
      }
      // The value part is the double forward kinematics.
      EXPECT_NEAR(T_jet.t[0].a, d.T_plus.t[0] - d.h * d.dt[0], 1e-3);
    }
  }
}

// The flange twists (RobotModel::ForwardWithTwists), the model's closed form and the Jet
// default alike, against central differences: d t / d p and the rotation vector of
// R(p + h) R(p - h)^T over 2h, at random joints and a perturbed table (betas off zero too).
TEST(SerialMdh, FlangeTwistsMatchCentralDifferences) {
  const auto model = Ur3();
  const int n = static_cast<int>(model->parameters().size());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), nudge(-0.05, 0.05);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> q(6), params = Nominal(*model);
    for (double& v : q) v = angle(rng);
    for (double& v : params) v += nudge(rng);
    Pose T_closed, T_jets;
    Eigen::Matrix<double, 6, Eigen::Dynamic> closed, jets;
    ASSERT_TRUE(model->ForwardWithTwists(q.data(), params.data(), &T_closed, &closed));
    ASSERT_TRUE(model->RobotModel::ForwardWithTwists(q.data(), params.data(), &T_jets, &jets));
    Pose T;
    ASSERT_TRUE(model->Forward(q.data(), params.data(), &T));
    EXPECT_LT((T_closed.t - T.t).norm(), 1e-12);
    EXPECT_LT((T_closed.R - T.R).norm(), 1e-14);
    ASSERT_EQ(closed.cols(), n);
    ASSERT_EQ(jets.cols(), n);
    for (int k = 0; k < n; ++k) {
      const testing::CentralDifference d =
          testing::CentralDifferenceByParameter(*model, q, params, k);
      Eigen::Matrix<double, 6, 1> numeric;
      numeric << d.dt, d.w;
      for (int i = 0; i < 6; ++i) {
        const double tolerance = 1e-6 * (1 + std::abs(numeric[i]));
        EXPECT_NEAR(closed(i, k), numeric[i], tolerance) << model->parameters()[k].name << " " << i;
        EXPECT_NEAR(jets(i, k), numeric[i], tolerance) << model->parameters()[k].name << " " << i;
        EXPECT_NEAR(closed(i, k), jets(i, k), 1e-9 * (1 + std::abs(jets(i, k))));
      }
    }
  }
}

TEST(SerialMdh, HayatiBetaIsZeroAndADFreedBetweenParallelAxesIsWarned) {
  const auto model = Ur3();
  for (const auto& p : model->parameters()) {
    if (p.name.find(".beta") != std::string::npos) {
      EXPECT_EQ(p.nominal, 0.0) << p.name;
    }
  }
  // d freed between parallel axes without the tilt: warned (joints 2-3 and 3-4 on a UR3).
  std::vector<Parameter> job = model->parameters();
  for (Parameter& p : job) p.fixed = p.name.find(".d") == std::string::npos;
  const auto warnings = model->Warnings(job);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("j3.beta"), std::string::npos);
  // Every entry free: beta carries the tilt, d is held by convention; nothing to warn of.
  for (Parameter& p : job) p.fixed = false;
  EXPECT_TRUE(model->Warnings(job).empty());
}

// The TX90L table against the vendor's URDF chain (ROS-Industrial staubli_experimental,
// tx2-90l_macro.xacro), written out here as its joint origins and axes: a user's check of a
// table converted from a URDF. Base frame: the URDF's `base` (478 mm above base_link).
Pose UrdfTx90lFlange(const std::vector<double>& q) {
  auto turn = [](const Eigen::Vector3d& axis, double angle) {
    return Pose{Eigen::AngleAxisd(angle, axis).toRotationMatrix(), Eigen::Vector3d::Zero()};
  };
  auto shift = [](double x, double y, double z) {
    return Pose{Eigen::Matrix3d::Identity(), Eigen::Vector3d(x, y, z)};
  };
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  return turn(z, q[0]) * shift(50, 0, 0) * turn(y, q[1]) * shift(0, 50, 500) * turn(y, q[2]) *
         turn(z, q[3]) * shift(0, 0, 550) * turn(y, q[4]) * shift(0, 0, 100) * turn(z, q[5]);
}

TEST(SerialMdh, StaubliTx90lTableReproducesTheVendorsUrdfChain) {
  const ConfigNode config =
      ConfigNode::LoadFile(testing::Source("configs/robots/staubli_tx90l.yaml"));
  const auto model = testing::Plugins().CreateRobotModel("serial_mdh", config);
  const std::vector<double> nominal = Nominal(*model);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> q(6);
    for (double& v : q) v = angle(rng);
    Pose T;
    ASSERT_TRUE(model->Forward(q.data(), nominal.data(), &T));
    const Pose urdf = UrdfTx90lFlange(q);
    EXPECT_LT((T.t - urdf.t).norm(), 1e-9);
    EXPECT_LT((T.R - urdf.R).norm(), 1e-12);
  }
  // All zero: straight up, the elbow's 50 mm sideways.
  const std::vector<double> zero(6, 0.0);
  Pose T;
  ASSERT_TRUE(model->Forward(zero.data(), nominal.data(), &T));
  EXPECT_LT((T.t - Eigen::Vector3d(50, 50, 1150)).norm(), 1e-9);
}

// What holding each entry at nominal means where the data cannot determine it: joint 1's
// entries put the base frame, the last joint's d and offset the flange frame, Hayati's tilt is
// zero between axes that are not parallel, and d is a convention between parallel ones.
TEST(SerialMdh, ConventionsAreTheParametrisationsOwnRedundancies) {
  const ConfigNode config =
      ConfigNode::LoadFile(testing::Source("configs/robots/staubli_tx90l.yaml"));
  const auto model = testing::Plugins().CreateRobotModel("serial_mdh", config);
  std::vector<std::string> conventions;
  for (const Parameter& p : model->parameters()) {
    if (!p.convention.empty()) conventions.push_back(p.name);
  }
  const std::vector<std::string> expected = {"j1.alpha",  "j1.a",    "j1.beta", "j1.d",
                                             "j1.offset", "j2.beta", "j3.d",    "j4.beta",
                                             "j5.beta",   "j6.beta", "j6.d",    "j6.offset"};
  EXPECT_EQ(conventions, expected);
}

TEST(SerialMdh, DegreesAndMetresAreConverted) {
  const ConfigNode config = ConfigNode::LoadString(
      "type: serial_mdh\nunits: {length: m, angle: deg}\njoints:\n"
      "  - {alpha: 90, a: 0.1, d: 0.2, offset: 180}\n",
      "inline.yaml");
  const auto model = testing::Plugins().CreateRobotModel("serial_mdh", config);
  const auto& p = model->parameters();
  EXPECT_NEAR(p[0].nominal, M_PI / 2, 1e-15);
  EXPECT_NEAR(p[1].nominal, 100.0, 1e-12);
  EXPECT_NEAR(p[3].nominal, 200.0, 1e-12);
  EXPECT_NEAR(p[4].nominal, M_PI, 1e-15);
}

TEST(SerialMdh, UnknownJointKeyIsRejectedWithASuggestion) {
  const ConfigNode config = ConfigNode::LoadString(
      "type: serial_mdh\njoints:\n  - {alpha: 0, a: 0, dd: 1}\n", "robot.yaml");
  try {
    testing::Plugins().CreateRobotModel("serial_mdh", config);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "robot.yaml");
    EXPECT_EQ(e.where().line, 3);
    EXPECT_NE(std::string(e.what()).find("Did you mean 'd'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cellmetry
