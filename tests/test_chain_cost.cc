// The analytic workcell Jacobian (core/src/chain_cost.h) and the SO(3) Jacobians it rests on,
// against central differences, at rotations far from the reference (up to ~1.5 rad).
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/basics/so3_jacobians.h"
#include "chain_cost.h"

namespace cellmetry {
namespace {

constexpr double kStep = 1e-6;

Eigen::Vector3d RandomVector(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Eigen::Vector3d(u(rng), u(rng), u(rng));
}

Pose RandomPose(std::mt19937& rng) {
  const Eigen::Vector3d rvec = RandomVector(rng, 1.5);
  return PoseFromRvecT(rvec, RandomVector(rng, 500.0));
}

TEST(So3Jacobians, LeftJacobianMatchesCentralDifferences) {
  std::mt19937 rng(3);
  for (double scale : {1e-7, 1e-3, 0.5, 2.5}) {
    const Eigen::Vector3d phi = RandomVector(rng, scale);
    const Eigen::Matrix3d R = RotationFromRvec(phi.data());
    Eigen::Matrix3d numeric;
    for (int j = 0; j < 3; ++j) {
      Eigen::Vector3d plus = phi, minus = phi;
      plus[j] += kStep;
      minus[j] -= kStep;
      // Exp(phi + d) R^T = Exp(J_l d): its rotation vector is the column.
      numeric.col(j) = (RotationError<double>(RotationFromRvec(plus.data()), R) -
                        RotationError<double>(RotationFromRvec(minus.data()), R)) /
                       (2 * kStep);
    }
    EXPECT_LT((LeftJacobian(phi) - numeric).norm(), 1e-8) << "scale " << scale;
    EXPECT_LT((InverseLeftJacobian(phi) * LeftJacobian(phi) - Eigen::Matrix3d::Identity()).norm(),
              1e-12)
        << "scale " << scale;
  }
}

struct ChainCase {
  ChainBlocks blocks;
  Compared compared;
};

class ChainCostTest : public ::testing::TestWithParam<ChainCase> {};

TEST_P(ChainCostTest, JacobianMatchesCentralDifferences) {
  const ChainCase c = GetParam();
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    FrameRefs refs;
    refs.world_base = RandomPose(rng).R;
    refs.flange_target = RandomPose(rng).R;
    refs.world_cam = RandomPose(rng).R;
    const Pose T_base_flange = RandomPose(rng), T_cam_world_fixed = RandomPose(rng);
    const int num_blocks = int(c.blocks.base) + int(c.blocks.tool) + int(c.blocks.camera);
    std::vector<std::array<double, 6>> values(num_blocks);
    for (auto& v : values) {
      const Eigen::Vector3d t = RandomVector(rng, 300.0), r = RandomVector(rng, 1.0);
      v = {t.x(), t.y(), t.z(), r.x(), r.y(), r.z()};
    }
    // The prediction, composed independently of ChainCost; the measurement is a small turn and
    // shift away from it, as near a solution (where Log is smooth).
    int k = 0;
    const Pose T_world_base =
        c.blocks.base ? FrameFromBlock(values[k++].data(), refs.world_base) : Pose::Identity();
    const Pose T_flange_target =
        c.blocks.tool ? FrameFromBlock(values[k++].data(), refs.flange_target) : Pose::Identity();
    const Pose T_cam_world = c.blocks.camera
                                 ? FrameFromBlock(values[k++].data(), refs.world_cam).inverse()
                                 : T_cam_world_fixed;
    const Pose predicted = c.blocks.base ? T_cam_world * T_world_base * T_base_flange *
                                               T_flange_target
                                         : T_cam_world;
    const Eigen::Vector3d turn = RandomVector(rng, 0.2);
    const Pose measured{RotationFromRvec(turn.data()) * predicted.R,
                        predicted.t + RandomVector(rng, 5.0)};
    TargetComparison comparison(c.compared, measured, Eigen::Vector3d(0.5, 0.7, 2.0));
    ChainCost cost(comparison, refs, c.blocks, T_base_flange, T_cam_world_fixed);
    ASSERT_EQ(cost.parameter_block_sizes().size(), size_t(num_blocks));

    std::vector<const double*> params;
    for (auto& v : values) params.push_back(v.data());
    std::vector<std::array<double, 18>> analytic(num_blocks);
    std::vector<double*> jac;
    for (auto& a : analytic) jac.push_back(a.data());
    double r[3];
    ASSERT_TRUE(cost.Evaluate(params.data(), r, jac.data()));

    for (int b = 0; b < num_blocks; ++b) {
      for (int j = 0; j < 6; ++j) {
        double plus[3], minus[3];
        const double saved = values[b][j];
        values[b][j] = saved + kStep;
        cost.Evaluate(params.data(), plus, nullptr);
        values[b][j] = saved - kStep;
        cost.Evaluate(params.data(), minus, nullptr);
        values[b][j] = saved;
        for (int i = 0; i < 3; ++i) {
          const double numeric = (plus[i] - minus[i]) / (2 * kStep);
          EXPECT_NEAR(analytic[b][i * 6 + j], numeric, 1e-6 * std::max(1.0, std::abs(numeric)))
              << "trial " << trial << " block " << b << " parameter " << j << " row " << i;
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    AllChains, ChainCostTest,
    ::testing::Values(ChainCase{{true, true, true}, Compared::kPosition},
                      ChainCase{{true, true, true}, Compared::kRotation},
                      ChainCase{{true, true, false}, Compared::kPosition},
                      ChainCase{{true, true, false}, Compared::kRotation},
                      ChainCase{{false, false, true}, Compared::kPosition},
                      ChainCase{{false, false, true}, Compared::kRotation}));

}  // namespace
}  // namespace cellmetry
