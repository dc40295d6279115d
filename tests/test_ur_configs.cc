// The Universal Robots configs (configs/robots/ur*.yaml) against UR's published standard DH
// tables, written here independently: the modified-DH rows put the flange where the standard DH
// chain Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i) does, at any joint angles (UR's own zero).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "support/test_support.h"

namespace cellmetry {
namespace {

struct PublishedDh {
  const char* config;
  double d1, a2, a3, d4, d5, d6;  // mm; a1 = d2 = d3 = 0, alpha = (pi/2, 0, 0, pi/2, -pi/2, 0)
};

// universal-robots.com, "DH parameters for calculations of kinematics and dynamics".
const PublishedDh kPublished[] = {
    {"ur3.yaml", 151.9, -243.65, -213.25, 112.35, 85.35, 81.9},
    {"ur5.yaml", 89.159, -425.0, -392.25, 109.15, 94.65, 82.3},
    {"ur10.yaml", 127.3, -612.0, -572.3, 163.941, 115.7, 92.2},
    {"ur3e.yaml", 151.85, -243.55, -213.2, 131.05, 85.35, 92.1},
    {"ur5e.yaml", 162.5, -425.0, -392.2, 133.3, 99.7, 99.6},
    {"ur10e.yaml", 180.7, -612.7, -571.55, 174.15, 119.85, 116.55},
    {"ur16e.yaml", 180.7, -478.4, -360.0, 174.15, 119.85, 116.55},
};

Eigen::Matrix4d StandardDhLink(double theta, double d, double a, double alpha) {
  Eigen::Matrix4d T;
  const double ct = std::cos(theta), st = std::sin(theta), ca = std::cos(alpha),
               sa = std::sin(alpha);
  T << ct, -st * ca, st * sa, a * ct,  //
      st, ct * ca, -ct * sa, a * st,   //
      0, sa, ca, d,                    //
      0, 0, 0, 1;
  return T;
}

Eigen::Matrix4d StandardDhFlange(const PublishedDh& ur, const std::vector<double>& q) {
  const double d[6] = {ur.d1, 0, 0, ur.d4, ur.d5, ur.d6};
  const double a[6] = {0, ur.a2, ur.a3, 0, 0, 0};
  const double alpha[6] = {M_PI / 2, 0, 0, M_PI / 2, -M_PI / 2, 0};
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 6; ++i) T = T * StandardDhLink(q[i], d[i], a[i], alpha[i]);
  return T;
}

TEST(UrConfigs, EachPutsTheFlangeWhereUrsPublishedDhDoes) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  for (const PublishedDh& ur : kPublished) {
    SCOPED_TRACE(ur.config);
    const auto model = testing::Plugins().CreateRobotModel(
        "serial_mdh",
        ConfigNode::LoadFile(testing::Source(std::string("configs/robots/") + ur.config)));
    std::vector<double> nominal;
    for (const Parameter& p : model->parameters()) nominal.push_back(p.nominal);
    for (int k = 0; k < 20; ++k) {
      std::vector<double> q(6);
      for (double& v : q) v = angle(rng);
      Pose flange;
      ASSERT_TRUE(model->Forward(q.data(), nominal.data(), &flange));
      const Eigen::Matrix4d expected = StandardDhFlange(ur, q);
      EXPECT_LT((flange.t - expected.topRightCorner<3, 1>()).norm(), 1e-9);
      EXPECT_LT((flange.R - expected.topLeftCorner<3, 3>()).norm(), 1e-12);
    }
  }
}

}  // namespace
}  // namespace cellmetry
