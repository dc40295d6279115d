// The evaluation caches of the cell layer (core/cell/src): a frame block's pose and left
// Jacobian per thread (frame_cache.h) and a capture's forward kinematics shared by its blocks
// (forward_memo.h). Each must give the same bits as computing afresh, whatever was asked
// before: repeats, other values, another R_ref at the same values, more frames than slots,
// the other Forward flavour, two threads at once.
#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "cellmetry/basics/so3_jacobians.h"
#include "effect_chain_cost.h"
#include "forward_memo.h"
#include "frame_cache.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

std::vector<double> RandomBlock(std::mt19937& rng) {
  std::uniform_real_distribution<double> t(-500, 500), r(-1.2, 1.2);
  return {t(rng), t(rng), t(rng), r(rng), r(rng), r(rng)};
}

Eigen::Matrix3d RandomRotation(std::mt19937& rng) {
  const std::vector<double> b = RandomBlock(rng);
  return RotationFromRvec(b.data() + 3);
}

bool SameBits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && (a.array() == b.array()).all();
}

// Fresh FrameFromBlock and LeftJacobian against the cache, over a sequence that revisits
// twelve (values, R_ref) pairs at random: more than the slots, and pairs that share values
// under another R_ref or an R_ref under other values.
TEST(FrameCache, SameBitsAsComputingWhateverCameBefore) {
  std::mt19937 rng(3);
  std::vector<std::vector<double>> blocks;
  std::vector<Eigen::Matrix3d> refs;
  for (int i = 0; i < 6; ++i) {
    blocks.push_back(RandomBlock(rng));
    refs.push_back(RandomRotation(rng));
  }
  std::vector<std::pair<int, int>> pairs;  // (block, R_ref)
  for (int i = 0; i < 6; ++i) pairs.push_back({i, i});
  for (int i = 0; i < 6; ++i) pairs.push_back({i, (i + 1) % 6});
  std::uniform_int_distribution<int> pick(0, static_cast<int>(pairs.size()) - 1);
  for (int step = 0; step < 2000; ++step) {
    const auto [b, r] = pairs[pick(rng)];
    const bool with_jacobian = step % 3 != 0;
    const CachedFrame got = FrameOfBlock(blocks[b].data(), refs[r], with_jacobian);
    const Pose fresh = FrameFromBlock(blocks[b].data(), refs[r]);
    ASSERT_TRUE(SameBits(got.T.R, fresh.R) && SameBits(got.T.t, fresh.t)) << "step " << step;
    if (with_jacobian) {
      const Eigen::Matrix3d J =
          LeftJacobian(Eigen::Vector3d(blocks[b][3], blocks[b][4], blocks[b][5]));
      ASSERT_TRUE(SameBits(got.J_left, J)) << "step " << step;
    }
  }
}

std::unique_ptr<RobotModel> Ur3() {
  return testing::Plugins().CreateRobotModel(
      "serial_mdh", ConfigNode::LoadFile(testing::Source("configs/robots/ur3_vsb2020.yaml")));
}

std::vector<double> Perturbed(const RobotModel& model, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> params;
  for (const auto& p : model.parameters()) {
    params.push_back(p.nominal + u(rng) * (p.unit == "mm" ? 2.0 : 0.02));
  }
  return params;
}

// The memo against the model itself, alternating parameter sets and flavours (Forward and
// ForwardWithTwists), then from two threads at once.
TEST(ForwardMemo, SameBitsAsTheModelForAnyParametersAndFlavour) {
  const auto ur3 = Ur3();
  std::mt19937 rng(5);
  const std::vector<double> q = {0.3, -1.1, 0.9, -0.4, 1.3, 0.2};
  const std::vector<std::vector<double>> sets = {Perturbed(*ur3, rng), Perturbed(*ur3, rng),
                                                 Perturbed(*ur3, rng)};
  ForwardMemo memo(ur3.get(), q.data());
  auto check = [&](int step) {
    const auto& params = sets[step % 3 == 2 ? 0 : (step / 2) % 3];
    const bool twists = (step / 3) % 2 == 0;
    Pose got, want;
    Eigen::Matrix<double, 6, Eigen::Dynamic> got_twists, want_twists;
    if (!memo.Forward(params.data(), &got, twists ? &got_twists : nullptr)) return false;
    if (twists) {
      ur3->ForwardWithTwists(q.data(), params.data(), &want, &want_twists);
      if (!SameBits(got_twists, want_twists)) return false;
    } else {
      ur3->Forward(q.data(), params.data(), &want);
    }
    return SameBits(got.R, want.R) && SameBits(got.t, want.t);
  };
  for (int step = 0; step < 60; ++step) ASSERT_TRUE(check(step)) << "step " << step;
  bool ok[2] = {true, true};
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t) {
    threads.emplace_back([&, t] {
      for (int step = t; step < 4000; step += 2) ok[t] = ok[t] && check(step);
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_TRUE(ok[0] && ok[1]);
}

// EffectChainCost with a memo shared by a position and a rotation block, against the same
// costs without one, at moving model parameters: residuals and every Jacobian, same bits.
TEST(ForwardMemo, EffectChainCostGivesTheSameBitsWithAndWithout) {
  const auto ur3 = Ur3();
  std::mt19937 rng(7);
  const std::vector<double> q = {-0.5, -1.3, 1.1, 0.6, -0.8, 1.9};
  EffectContext context;
  context.num_joints = 6;
  context.q = q.data();
  context.camera = "cam1";
  context.target = "tool";
  FrameRefs refs;
  refs.world_base = RandomRotation(rng);
  refs.flange_target = RandomRotation(rng);
  refs.world_cam = RandomRotation(rng);
  const Pose measured{RandomRotation(rng), Eigen::Vector3d(10, -20, 900)};
  auto memo = std::make_shared<ForwardMemo>(ur3.get(), q.data());
  for (Compared compared : {Compared::kPosition, Compared::kRotation}) {
    const TargetComparison comparison(compared, measured, Eigen::Vector3d(0.5, 0.7, 2.0));
    const EffectChainCost shared(
        comparison, std::make_shared<const FrameRefs>(refs), ur3.get(), context, true,
        Pose::Identity(),
        std::make_shared<const ChainEffectList>(std::vector<const Effect*>{}, std::vector<int>{}),
        memo);
    const EffectChainCost alone(comparison, refs, ur3.get(), context, true, Pose::Identity(), {},
                                {});
    for (int trial = 0; trial < 6; ++trial) {
      std::vector<std::vector<double>> values = {RandomBlock(rng), RandomBlock(rng),
                                                 RandomBlock(rng), Perturbed(*ur3, rng)};
      if (trial % 2 == 1) values[3] = Perturbed(*ur3, rng);
      std::vector<const double*> params;
      for (const auto& v : values) params.push_back(v.data());
      std::vector<std::vector<double>> J_shared, J_alone;
      std::vector<double*> p_shared, p_alone;
      for (const auto& v : values) {
        J_shared.emplace_back(3 * v.size());
        J_alone.emplace_back(3 * v.size());
        p_shared.push_back(J_shared.back().data());
        p_alone.push_back(J_alone.back().data());
      }
      // Residuals alone (the memo's Forward without twists), then with every Jacobian.
      double r_shared[3], r_alone[3], r_plain_shared[3], r_plain_alone[3];
      ASSERT_TRUE(shared.Evaluate(params.data(), r_plain_shared, nullptr));
      ASSERT_TRUE(alone.Evaluate(params.data(), r_plain_alone, nullptr));
      ASSERT_TRUE(shared.Evaluate(params.data(), r_shared, p_shared.data()));
      ASSERT_TRUE(alone.Evaluate(params.data(), r_alone, p_alone.data()));
      for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(r_shared[i], r_alone[i]);
        EXPECT_EQ(r_plain_shared[i], r_plain_alone[i]);
      }
      for (size_t b = 0; b < values.size(); ++b) EXPECT_EQ(J_shared[b], J_alone[b]) << b;
    }
  }
}

}  // namespace
}  // namespace cellmetry
