// The `gradient_descent` solver (Adam, as ML calibrations train) against Levenberg-Marquardt on
// the same assembled sim_b problem, its honesty about the epoch limit, and its option checks.
#include <gtest/gtest.h>

#include "cellmetry/basics/transform.h"
#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell_assembly.h"
#include "cellmetry/cell/workcell_initial.h"
#include "cellmetry/estimation/noise_model.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

struct Solved {
  SolverSummary summary;
  Eigen::Vector3d base_t;
  double cost_left = 0.0;  // 0.5 |r|^2 at the values the solver left in the Problem
};

// sim_b assembled as bench_workcell's BM_Solve does, solved by `solver_yaml`. The closed-form
// start is already within 0.2 mm of the answer, so `far_start` moves the base by 36 mm and
// 3 degrees and the tool by 12 mm, to make the solver travel.
Solved SolveSimB(const std::string& solver_yaml, bool far_start = false) {
  Registry& registry = testing::Plugins();
  static const WorkcellJob job =
      LoadWorkcellJob(testing::Source("configs/jobs/vsb_sim_b.yaml"), registry);
  static const Recording recording = ReadRecording(job.recording);
  const WorkcellData data = PrepareWorkcellData(job.problem, recording);
  NoiseSpec noise_spec = job.problem.noise;
  noise_spec.position_sigma_mm["cam1"] = Eigen::Vector3d(0.56, 0.52, 0.31);
  const NoiseModel noise = BuildNoiseModel(recording, noise_spec);
  WorkcellEstimate start = InitialEstimate(job.problem, recording, data);
  if (far_start) {
    Pose& base = start.T_world_base.at("ur3");
    base.t += Eigen::Vector3d(20.0, -15.0, 25.0);
    base.R = RotationFromRvec(Eigen::Vector3d(0.03, -0.02, 0.04).eval().data()) * base.R;
    start.T_flange_target.at("tool").t += Eigen::Vector3d(5.0, -5.0, 10.0);
  }
  auto assembled = AssembleWorkcell(job.problem, recording, data, noise, start);
  const ConfigNode config = ConfigNode::LoadString(solver_yaml, "solver");
  Solved solved;
  solved.summary =
      registry.CreateSolver(config["type"].AsString(), config)->Solve(assembled->problem);
  solved.base_t = ReadEstimate(job.problem, *assembled).T_world_base.at("ur3").t;
  assembled->problem.Evaluate(&solved.cost_left, nullptr, nullptr);
  return solved;
}

// From the far start (cost 2e6, 751 at the answer) Adam needs a learning rate near 1 sigma-unit
// per epoch; PyTorch's default 1e-3 would need far more epochs than a unit test affords.
TEST(GradientDescent, ReachesTheLevenbergMarquardtBaseOnSimB) {
  const Solved lm = SolveSimB("type: ceres_lm", /*far_start=*/true);
  ASSERT_TRUE(lm.summary.converged) << lm.summary.stop_reason;
  const Solved gd = SolveSimB(
      "{type: gradient_descent, learning_rate: 2, epochs: 2000, gradient_tolerance: 1e-6}",
      /*far_start=*/true);
  EXPECT_EQ(gd.summary.solver, "gradient_descent");
  EXPECT_LT((gd.base_t - lm.base_t).norm(), 0.5)
      << "gradient descent " << gd.base_t.transpose() << " vs LM " << lm.base_t.transpose() << "; "
      << gd.summary.stop_reason;
  EXPECT_TRUE(gd.summary.converged) << gd.summary.stop_reason;
  EXPECT_LT(gd.summary.iterations, 2000);
  EXPECT_EQ(gd.summary.evaluations, gd.summary.iterations + 1);
  EXPECT_NE(gd.summary.stop_reason.find("< gradient_tolerance"), std::string::npos)
      << gd.summary.stop_reason;
  EXPECT_NEAR(gd.summary.final_cost, lm.summary.final_cost, 1e-6 * lm.summary.final_cost);
  EXPECT_GT(gd.summary.initial_cost, 1000 * gd.summary.final_cost);  // it did travel
  // The Problem is left at the values whose cost is reported (the best seen).
  EXPECT_DOUBLE_EQ(gd.cost_left, gd.summary.final_cost);
}

TEST(GradientDescent, ReportsTheEpochLimitHonestly) {
  const Solved gd = SolveSimB("{type: gradient_descent, epochs: 3}");
  EXPECT_FALSE(gd.summary.converged);
  EXPECT_EQ(gd.summary.iterations, 3);
  EXPECT_EQ(gd.summary.evaluations, 4);  // the start and one per epoch
  EXPECT_NE(gd.summary.stop_reason.find("3 epochs done (limit)"), std::string::npos)
      << gd.summary.stop_reason;
  EXPECT_DOUBLE_EQ(gd.cost_left, gd.summary.final_cost);
}

TEST(GradientDescent, ConvergedOnlyWhenAToleranceStopsIt) {
  const Solved gd = SolveSimB("{type: gradient_descent, cost_tolerance: 1e300}");
  EXPECT_TRUE(gd.summary.converged);
  EXPECT_EQ(gd.summary.iterations, 0);
  EXPECT_NE(gd.summary.stop_reason.find("< cost_tolerance"), std::string::npos)
      << gd.summary.stop_reason;
}

InputError CreateError(const std::string& yaml) {
  return testing::CatchInputError([&] {
    const ConfigNode config = ConfigNode::LoadString(yaml, "solver");
    testing::Plugins().CreateSolver("gradient_descent", config);
  });
}

TEST(GradientDescent, RejectsBadOptions) {
  const InputError unknown = CreateError("{type: gradient_descent, learning_rat: 0.1}");
  EXPECT_NE(std::string(unknown.what()).find("learning_rate"), std::string::npos)
      << unknown.what();  // the near miss is suggested
  const InputError negative = CreateError("{type: gradient_descent, learning_rate: -0.1}");
  EXPECT_NE(negative.message().find("learning_rate: must be positive"), std::string::npos)
      << negative.message();
  EXPECT_FALSE(negative.hint().empty());
  const InputError beta = CreateError("{type: gradient_descent, beta2: 1}");
  EXPECT_NE(beta.message().find("[0, 1)"), std::string::npos) << beta.message();
  CreateError("{type: gradient_descent, epochs: 0}");
}

}  // namespace
}  // namespace cellmetry
