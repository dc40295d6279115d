// The analytic workcell Jacobian (core/src/chain_cost.h) and the SO(3) Jacobians it rests on,
// against central differences, at rotations far from the reference (up to ~1.5 rad).
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include <ceres/dynamic_autodiff_cost_function.h>

#include "cellmetry/basics/so3_jacobians.h"
#include "chain_cost.h"
#include "effect_chain_cost.h"
#include "support/test_support.h"
#include "whole_chain_jets.h"

namespace cellmetry {
namespace {

constexpr double kStep = 1e-6;

// d residual / d *value of a three-row cost by central differences, *value restored after.
std::array<double, 3> CentralDifference(const ceres::CostFunction& cost,
                                        const std::vector<const double*>& params, double* value) {
  double plus[3], minus[3];
  const double saved = *value;
  *value = saved + kStep;
  cost.Evaluate(params.data(), plus, nullptr);
  *value = saved - kStep;
  cost.Evaluate(params.data(), minus, nullptr);
  *value = saved;
  std::array<double, 3> numeric;
  for (int i = 0; i < 3; ++i) numeric[i] = (plus[i] - minus[i]) / (2 * kStep);
  return numeric;
}

// d tangent / d *value of a shared prediction (shared_prediction_cost.h) by central
// differences: the position's, or the left rotation Log(R(+) R(-)^T) / 2h for a rotation.
std::array<double, 3> TangentDifference(const SharedPredictionCost& cost, Compared compared,
                                        const std::vector<const double*>& params, double* value) {
  Pose plus, minus;
  const double saved = *value;
  *value = saved + kStep;
  cost.Predict(params.data(), &plus, nullptr);
  *value = saved - kStep;
  cost.Predict(params.data(), &minus, nullptr);
  *value = saved;
  Eigen::Vector3d d = plus.t - minus.t;
  if (compared == Compared::kRotation) d = RvecFromRotation(plus.R * minus.R.transpose());
  std::array<double, 3> numeric;
  for (int i = 0; i < 3; ++i) numeric[i] = d[i] / (2 * kStep);
  return numeric;
}

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

// The fused form is the separate ones, at every angle from the series' range to beyond 2.5 rad
// (where it hands over to them), about random axes and from random reference rotations.
TEST(So3Jacobians, RotationErrorAndInverseJacobianAreTheSeparateForms) {
  std::mt19937 rng(5);
  for (double angle : {0.0, 1e-9, 3e-5, 1e-4, 2e-4, 1e-2, 0.3, 1.5, 2.49, 2.51, 3.1}) {
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Vector3d phi = angle * RandomVector(rng, 1.0).normalized();
      const Eigen::Matrix3d R_b = RandomPose(rng).R;
      const Eigen::Matrix3d R_a = RotationFromRvec(phi.data()) * R_b;
      Eigen::Vector3d fused;
      Eigen::Matrix3d fused_inverse;
      RotationErrorAndInverseJacobian(R_a, R_b, &fused, &fused_inverse);
      const Eigen::Vector3d separate = RotationError<double>(R_a, R_b);
      EXPECT_LT((fused - separate).norm(), 1e-13 * std::max(1.0, angle)) << "angle " << angle;
      EXPECT_LT((fused - phi).norm(), 1e-12 * std::max(1.0, angle)) << "angle " << angle;
      EXPECT_LT((fused_inverse - InverseLeftJacobian(separate)).norm(), 1e-11) << "angle " << angle;
    }
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
    const Pose predicted =
        c.blocks.base ? T_cam_world * T_world_base * T_base_flange * T_flange_target : T_cam_world;
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
        const std::array<double, 3> numerics = CentralDifference(cost, params, &values[b][j]);
        for (int i = 0; i < 3; ++i) {
          const double numeric = numerics[i];
          EXPECT_NEAR(analytic[b][i * 6 + j], numeric, 1e-6 * std::max(1.0, std::abs(numeric)))
              << "trial " << trial << " block " << b << " parameter " << j << " row " << i;
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllChains, ChainCostTest,
                         ::testing::Values(ChainCase{{true, true, true}, Compared::kPosition},
                                           ChainCase{{true, true, true}, Compared::kRotation},
                                           ChainCase{{true, true, false}, Compared::kPosition},
                                           ChainCase{{true, true, false}, Compared::kRotation},
                                           ChainCase{{false, false, true}, Compared::kPosition},
                                           ChainCase{{false, false, true}, Compared::kRotation}));

// EffectChainCost (effect_chain_cost.h): a UR3 chain with measurement effects (a target's
// printed scale, a camera's focal length, principal point and distortion), and for a carried
// target joint effects (compliance, backlash, gear error) and a flange effect (thermal growth),
// all off zero; each
// block's Jacobian against central differences and against the Jets over the whole chain it
// replaces (EffectChainResidual, WorldEffectResidual), with the residuals themselves; and split
// as a shared prediction (Predict's tangent Jacobian against central differences, Compare's
// D times it against the block's Jacobian).
struct EffectChainCase {
  bool robot;          // a carried target (else the world target)
  bool static_camera;  // a camera block (else the measured per-frame camera)
  Compared compared;
};

class EffectChainCostTest : public ::testing::TestWithParam<EffectChainCase> {};

std::unique_ptr<Effect> MakeEffect(const std::string& yaml, const RobotModel& robot) {
  const ConfigNode config = ConfigNode::LoadString(yaml, "test");
  return testing::Plugins().CreateEffect(config["type"].AsString(), config, robot);
}

TEST_P(EffectChainCostTest, JacobianMatchesCentralDifferencesAndTheJets) {
  const EffectChainCase c = GetParam();
  const auto ur3 = testing::Plugins().CreateRobotModel(
      "serial_mdh", ConfigNode::LoadFile(testing::Source("configs/robots/ur3_vsb2020.yaml")));
  const auto scale = MakeEffect("{type: target_scale, targets: [tool, world]}", *ur3);
  const auto intrinsics = MakeEffect("{type: camera_intrinsics, cameras: [cam2, cam1]}", *ur3);
  // A carried target's chain also has effects at the joints (through the model's offsets) and
  // at the flange, between the measurement effects so that each stage's columns are mixed in.
  const auto compliance = MakeEffect("{type: joint_compliance, joints: [2, 3]}", *ur3);
  const auto backlash = MakeEffect("{type: backlash, joints: [1, 5]}", *ur3);
  const auto gear =  // 12 parameters: more than one Jet pass
      MakeEffect("{type: transmission_error, joints: [4, 6], harmonics: [1, 2, 3]}", *ur3);
  const auto thermal = MakeEffect("{type: thermal_drift}", *ur3);
  std::vector<const Effect*> effects = {scale.get(), intrinsics.get()};
  if (c.robot) {
    effects = {compliance.get(), scale.get(),      thermal.get(),
               backlash.get(),   intrinsics.get(), gear.get()};
  }
  std::vector<int> effect_sizes;
  for (const Effect* e : effects) effect_sizes.push_back(int(e->parameters().size()));
  std::mt19937 rng(17);
  for (int trial = 0; trial < 10; ++trial) {
    FrameRefs refs;
    refs.world_base = RandomPose(rng).R;
    refs.flange_target = RandomPose(rng).R;
    refs.world_cam = RandomPose(rng).R;
    std::vector<double> q(6);
    for (double& v : q) v = RandomVector(rng, 3.0)[0];
    EffectContext context;
    context.num_joints = 6;
    context.q = q.data();
    context.camera = "cam1";
    context.target = c.robot ? "tool" : "world";
    const std::vector<int> approach = {1, -1, 1, 0, -1, 1};
    context.approach = approach.data();
    context.temperature_c = 31.0;
    std::vector<double> nominal;
    for (const auto& p : ur3->parameters()) nominal.push_back(p.nominal);
    std::vector<Pose> T_base_joint;  // gravity torques act at the nominal geometry (effect.h)
    ASSERT_TRUE(ur3->JointFrames(q.data(), nominal.data(), &T_base_joint));
    context.T_base_joint = &T_base_joint;
    // Blocks in the cost's order, values off zero everywhere.
    std::vector<std::vector<double>> values;
    auto frame = [&] {
      const Eigen::Vector3d t = RandomVector(rng, 300.0), r = RandomVector(rng, 0.8);
      values.push_back({t.x(), t.y(), t.z(), r.x(), r.y(), r.z()});
    };
    if (c.robot) frame(), frame();
    if (c.static_camera) frame();
    if (c.robot) {
      values.emplace_back();
      for (const auto& p : ur3->parameters()) {
        values.back().push_back(p.nominal + RandomVector(rng, p.unit == "mm" ? 2.0 : 0.02)[0]);
      }
    }
    for (int size : effect_sizes) {
      values.emplace_back();
      for (int i = 0; i < size; ++i) values.back().push_back(RandomVector(rng, 0.02)[0]);
    }
    std::vector<const double*> params;
    for (auto& v : values) params.push_back(v.data());
    // The camera where a camera is: the target 0.6 to 1.2 m in front of it, off its axis.
    Pose T_world_target = Pose::Identity();
    if (c.robot) {
      Pose T_base_flange;
      ASSERT_TRUE(ur3->Forward(q.data(), params[c.static_camera ? 3 : 2], &T_base_flange));
      T_world_target = FrameFromBlock(params[0], refs.world_base) * T_base_flange *
                       FrameFromBlock(params[1], refs.flange_target);
    }
    Pose T_world_cam = RandomPose(rng);
    if (c.static_camera) T_world_cam = FrameFromBlock(params[c.robot ? 2 : 0], refs.world_cam);
    const Eigen::Vector3d in_view(RandomVector(rng, 200.0)[0], RandomVector(rng, 200.0)[1],
                                  900.0 + RandomVector(rng, 300.0)[2]);
    T_world_cam.t = T_world_target.t - T_world_cam.R * in_view;
    if (c.static_camera) {
      auto& camera = values[c.robot ? 2 : 0];
      for (int i = 0; i < 3; ++i) camera[i] = T_world_cam.t[i];
    }
    const Pose T_cam_world_measured = T_world_cam.inverse();
    // The measurement: the prediction (with the effects at zero) turned and shifted a little.
    const Pose predicted = T_cam_world_measured * T_world_target;
    const Eigen::Vector3d turn = RandomVector(rng, 0.2);
    const Pose measured{RotationFromRvec(turn.data()) * predicted.R,
                        predicted.t + RandomVector(rng, 5.0)};
    const TargetComparison comparison(c.compared, measured, Eigen::Vector3d(0.5, 0.7, 2.0));

    EffectChainCost cost(comparison, refs, c.robot ? ur3.get() : nullptr, context, c.static_camera,
                         T_cam_world_measured, effects, effect_sizes);
    std::unique_ptr<ceres::CostFunction> jets;
    if (c.robot) {
      jets.reset(new ceres::DynamicAutoDiffCostFunction<EffectChainResidual, kJetStride>(
          new EffectChainResidual(comparison, refs, ur3.get(), context, c.static_camera,
                                  T_cam_world_measured, effects)));
    } else {
      jets.reset(new ceres::DynamicAutoDiffCostFunction<WorldEffectResidual, kJetStride>(
          new WorldEffectResidual(comparison, refs.world_cam, context, effects)));
    }
    auto* dynamic = static_cast<ceres::DynamicCostFunction*>(jets.get());
    for (const auto& v : values) dynamic->AddParameterBlock(static_cast<int>(v.size()));
    dynamic->SetNumResiduals(3);
    ASSERT_EQ(cost.parameter_block_sizes(), jets->parameter_block_sizes());

    std::vector<std::vector<double>> analytic, reference;
    std::vector<double*> analytic_ptr, reference_ptr;
    for (const auto& v : values) {
      analytic.emplace_back(3 * v.size());
      reference.emplace_back(3 * v.size());
    }
    for (size_t b = 0; b < values.size(); ++b) {
      analytic_ptr.push_back(analytic[b].data());
      reference_ptr.push_back(reference[b].data());
    }
    double r[3], r_jets[3];
    ASSERT_TRUE(cost.Evaluate(params.data(), r, analytic_ptr.data()));
    ASSERT_TRUE(jets->Evaluate(params.data(), r_jets, reference_ptr.data()));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i], r_jets[i], 1e-9 * (1 + std::abs(r_jets[i])));
    double r_plain[3];
    ASSERT_TRUE(cost.Evaluate(params.data(), r_plain, nullptr));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(r_plain[i], r[i], 1e-12 * (1 + std::abs(r[i])));

    // The same split as a shared prediction: Compare at Predict's measured pose gives r, and
    // D A the Jacobian; A itself against central differences of the measured pose.
    std::vector<std::vector<double>> tangent(values.size());
    std::vector<double*> tangent_ptr;
    for (size_t b = 0; b < values.size(); ++b) {
      tangent[b].resize(3 * values[b].size());
      tangent_ptr.push_back(tangent[b].data());
    }
    Pose prediction, plain_prediction;
    ASSERT_TRUE(cost.Predict(params.data(), &prediction, tangent_ptr.data()));
    ASSERT_TRUE(cost.Predict(params.data(), &plain_prediction, nullptr));
    EXPECT_LT((prediction.t - plain_prediction.t).norm(), 1e-9);
    EXPECT_LT((prediction.R - plain_prediction.R).norm(), 1e-12);
    double r_shared[3];
    Eigen::Matrix3d D;
    cost.Compare(prediction, r_shared, &D);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(r_shared[i], r[i], 1e-9 * (1 + std::abs(r[i])));

    for (size_t b = 0; b < values.size(); ++b) {
      const int width = static_cast<int>(values[b].size());
      for (int j = 0; j < width; ++j) {
        const std::array<double, 3> tangents =
            TangentDifference(cost, c.compared, params, &values[b][j]);
        const Eigen::Vector3d A(tangent[b][j], tangent[b][width + j], tangent[b][2 * width + j]);
        const Eigen::Vector3d DA = D * A;
        for (int i = 0; i < 3; ++i) {
          EXPECT_NEAR(A[i], tangents[i], 1e-6 * std::max(1.0, std::abs(tangents[i])))
              << "trial " << trial << " block " << b << " parameter " << j << " tangent " << i;
          const double a = analytic[b][i * width + j];
          EXPECT_NEAR(DA[i], a, 1e-9 * std::max(1.0, std::abs(a)))
              << "trial " << trial << " block " << b << " parameter " << j << " row " << i;
        }
      }
    }

    for (size_t b = 0; b < values.size(); ++b) {
      const int width = static_cast<int>(values[b].size());
      for (int j = 0; j < width; ++j) {
        const std::array<double, 3> numerics = CentralDifference(cost, params, &values[b][j]);
        for (int i = 0; i < 3; ++i) {
          const double numeric = numerics[i];
          const double a = analytic[b][i * width + j], jet = reference[b][i * width + j];
          EXPECT_NEAR(a, numeric, 1e-6 * std::max(1.0, std::abs(numeric)))
              << "trial " << trial << " block " << b << " parameter " << j << " row " << i;
          EXPECT_NEAR(a, jet, 1e-9 * std::max(1.0, std::abs(jet)))
              << "trial " << trial << " block " << b << " parameter " << j << " row " << i;
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllChains, EffectChainCostTest,
                         ::testing::Values(EffectChainCase{true, true, Compared::kPosition},
                                           EffectChainCase{true, true, Compared::kRotation},
                                           EffectChainCase{true, false, Compared::kPosition},
                                           EffectChainCase{true, false, Compared::kRotation},
                                           EffectChainCase{false, true, Compared::kPosition},
                                           EffectChainCase{false, true, Compared::kRotation}));

}  // namespace
}  // namespace cellmetry
