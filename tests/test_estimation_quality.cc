// Identifiability: parameters the data cannot determine are named and held, never returned as
// silent garbage.
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/estimation/robust_covariance.h"
#include "cellmetry/formats/config_node.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

TEST(Identifiability, TiedParametersAreNamedAndHeld) {
  const ConfigNode config =
      ConfigNode::LoadFile(testing::Source("configs/robots/ur3_vsb2020.yaml"));
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
  const WorkcellResult result = IdentifyWorkcell(
      problem, recording, [&] { return testing::Plugins().CreateSolver("ceres_lm", solver); });
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
  const std::vector<Eigen::VectorXd> values = {
      Eigen::Vector2d(1.0, 0.01), Eigen::Vector2d(-1.0, -0.01), Eigen::Vector2d(0.0, 0.0)};
  const Jackknife jack = JackknifeSpread(values);
  EXPECT_NEAR(jack.variance[0], 2.0 / 3.0 * 2.0, 1e-12);  // (n-1)/n sum of squares
  EXPECT_EQ(jack.groups[0], 3);
  Uncertainty u;
  u.sigma = Eigen::Vector2d(0.1, 0.1);
  CombineUncertainty(Eigen::MatrixXd(), jack, &u);
  EXPECT_NEAR(u.sigma_systematic[0], std::sqrt(4.0 / 3.0 - 0.01), 1e-12);  // far beyond chance
  EXPECT_EQ(u.sigma_systematic[1], 0.0);                                   // within chance
  EXPECT_NEAR(u.sigma[1], 0.1, 1e-12);
}

}  // namespace
}  // namespace cellmetry

namespace cellmetry {
namespace {

// (value[0] - y) / sigma: one measurement of a block's first entry.
struct Measured {
  double y, sigma;
  template <typename T>
  bool operator()(const T* value, T* residual) const {
    residual[0] = (value[0] - T(y)) / T(sigma);
    return true;
  }
};

// A problem measuring one block {m, b} through `ys` (residual block k: the k-th pose, in capture
// order), b measured by nothing.
void AddMeasurements(Problem* problem, const std::vector<double>& ys, double sigma) {
  Parameter m;
  m.name = "m";
  m.unit = "mm";
  Parameter b;
  b.name = "b";
  b.unit = "mm";
  const int block = problem->AddBlock("x", {m, b});
  for (size_t k = 0; k < ys.size(); ++k) {
    ResidualInfo info;
    info.sigma = Eigen::Vector3d::Constant(sigma);
    problem->AddResidual(
        std::make_unique<ceres::AutoDiffCostFunction<Measured, 1, 2>>(new Measured{ys[k], sigma}),
        {block}, info);
  }
}

std::vector<double> Ar1(int n, double rho, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> e(0.0, 1.0);
  std::vector<double> y(static_cast<size_t>(n));
  double last = e(rng) / std::sqrt(1.0 - rho * rho);
  for (double& v : y) v = last = rho * last + e(rng);
  return y;
}

// The mean of an AR(1) series with rho = 0.6: its variance is (1 + rho) / (1 - rho) = 4 times
// what independent errors of the same spread give, so sigma twice the model's; with rho = 0,
// the model's. The bandwidth follows (Andrews 1991: about 10 for rho = 0.6 at T = 250).
TEST(SerialClusterRobust, NeighbouringErrorsWidenSigmaByTheirLongRunVariance) {
  for (const double rho : {0.0, 0.6}) {
    Problem problem;
    AddMeasurements(&problem, Ar1(4000, rho, 3), 1.0);
    problem.SetFixed(0, 1, true);
    problem.Build();
    const auto solver = testing::Plugins().CreateSolver(
        "ceres_lm", ConfigNode::LoadString("type: ceres_lm", "solver"));
    solver->Solve(problem);
    const Linearization at = Linearize(problem);
    const Uncertainty model = ComputeUncertainty(problem, at);
    std::vector<int> clusters;  // each measurement its own pose, in capture order
    for (size_t k = 0; k < problem.residual_infos().size(); ++k) {
      clusters.push_back(static_cast<int>(k));
    }
    const ClusterRobust serial = SerialClusterRobustCovariance(problem, at, clusters, model);
    const double ratio = std::sqrt(serial.covariance(0, 0)) / model.sigma[0];
    if (rho == 0.0) {
      EXPECT_NEAR(ratio, 1.0, 0.15);
      EXPECT_LE(serial.lag, 3);
    } else {
      EXPECT_NEAR(ratio, 2.0, 0.35);
      EXPECT_GE(serial.lag, 10);
    }
  }
  std::vector<Eigen::VectorXd> series;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const auto y = Ar1(250, 0.6, seed);
    series.push_back(Eigen::Map<const Eigen::VectorXd>(y.data(), 250));
  }
  EXPECT_NEAR(BartlettBandwidth(series), 10, 4);
}

// A prior is a stated input: where the measurements are noisier than stated (chi-square 9 times
// their count), sigma of what they determine is scaled by 3, and a parameter only its prior
// determines keeps the prior's sigma.
TEST(ComputeUncertainty, APriorKeepsItsSigmaWhenTheDataAreNoisierThanStated) {
  Problem problem;
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 3.0);
  std::vector<double> ys(400);
  for (double& y : ys) y = 5.0 + noise(rng);
  AddMeasurements(&problem, ys, 1.0);
  problem.SetPrior(0, 1, 0.0, 0.5);
  problem.Build();
  const auto solver = testing::Plugins().CreateSolver(
      "ceres_lm", ConfigNode::LoadString("type: ceres_lm", "solver"));
  solver->Solve(problem);
  const Uncertainty u = ComputeUncertainty(problem);
  EXPECT_NEAR(u.scale, 9.0, 1.5);
  EXPECT_NEAR(u.sigma[0], std::sqrt(u.scale / 400.0), 1e-9);
  EXPECT_NEAR(u.sigma[1], 0.5, 1e-9);
  // The bread of every sandwich is the unscaled inverse information, the prior's included.
  EXPECT_NEAR(u.inverse_information(1, 1), 0.25, 1e-12);
}

}  // namespace
}  // namespace cellmetry
