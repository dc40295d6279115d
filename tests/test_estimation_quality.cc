// Identifiability: parameters the data cannot determine are named and held, never returned as
// silent garbage.
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/estimation/robust_covariance.h"
#include "cellmetry/formats/config_node.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

TEST(Identifiability, TiedParametersAreNamedAndHeld) {
  const ConfigNode config = ConfigNode::LoadFile(testing::Source("configs/robots/ur3.yaml"));
  std::shared_ptr<const RobotModel> model =
      testing::Plugins().CreateRobotModel("serial_mdh", config);
  WorkcellSimulationSpec sim;
  SimulatedRobot robot;
  robot.name = "ur3";
  robot.model = model;
  for (const auto& p : model->parameters()) robot.model_values.push_back(p.nominal);
  robot.T_world_base = PoseFromRvecT({0, 0, 0.2}, {400, 500, -450});
  robot.T_flange_target["tool"] = PoseFromRvecT({0, 0, 0}, {0, 0, 66});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> q(-M_PI, M_PI);
  for (int i = 0; i < 40; ++i)
    robot.joint_poses.push_back({q(rng), q(rng), q(rng), q(rng), q(rng), q(rng)});
  sim.robots.push_back(robot);
  sim.T_world_cam["cam1"] = PoseFromRvecT({1.48, -2.65, -0.07}, {440, 404, 811});
  const Recording recording = SimulateWorkcell(sim, nullptr);

  WorkcellProblem problem;
  WorkcellRobot job;
  job.name = "ur3";
  job.model = model;
  job.model_parameters = model->parameters();
  // j1.d moves the flange along the base z axis exactly like the base's own z: not separable.
  for (auto& p : job.model_parameters) p.fixed = p.name != "j1.d";
  job.base.free.fill(true);
  WorkcellTool tool;
  tool.target = "tool";
  tool.flange_tool.free = {true, true, true, true, false, false};  // rx: position-only data
  job.tools.push_back(tool);
  problem.robots.push_back(job);
  problem.folds = 0;
  const ConfigNode solver = ConfigNode::LoadString("type: ceres_lm", "solver");
  const WorkcellResult result = IdentifyWorkcell(problem, recording, [&] {
    return testing::Plugins().CreateSolver("ceres_lm", solver);
  });
  std::set<std::string> held;
  for (const auto& u : result.unidentifiable) held.insert(u.name);
  EXPECT_TRUE(held.count("tool.rx")) << "a rotation of a point target is invisible";
  EXPECT_TRUE(held.count("ur3.base.z") || held.count("ur3.model.j1.d"));
  // What is left is determined exactly (noise-free data).
  for (const auto& f : result.frames) {
    if (f.name == "ur3.base") {
      EXPECT_NEAR(f.pose.t.x(), 400.0, 1e-6);
    }
  }
  EXPECT_LT(result.uncertainty.condition_number, 1e6);
}

}  // namespace
}  // namespace cellmetry

namespace cellmetry {
namespace {

// The jackknife spread of leave-one-out estimates, and a systematic part only beyond chance.
TEST(RobustCovariance, JackknifeClaimsASystematicPartOnlyBeyondChance) {
  const std::vector<Eigen::VectorXd> values = {Eigen::Vector2d(1.0, 0.01),
                                               Eigen::Vector2d(-1.0, -0.01),
                                               Eigen::Vector2d(0.0, 0.0)};
  const Jackknife jack = JackknifeSpread(values);
  EXPECT_NEAR(jack.variance[0], 2.0 / 3.0 * 2.0, 1e-12);  // (n-1)/n sum of squares
  EXPECT_EQ(jack.groups[0], 3);
  Uncertainty u;
  u.sigma = Eigen::Vector2d(0.1, 0.1);
  CombineUncertainty(Eigen::MatrixXd(), jack, &u);
  EXPECT_NEAR(u.sigma_systematic[0], std::sqrt(4.0 / 3.0 - 0.01), 1e-12);  // far beyond chance
  EXPECT_EQ(u.sigma_systematic[1], 0.0);                                 // within chance
  EXPECT_NEAR(u.sigma[1], 0.1, 1e-12);
}

}  // namespace
}  // namespace cellmetry
