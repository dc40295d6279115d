// The effect library (plugins/effects) and its place in the workcell identification: exact
// derivatives, "zero is no effect", the facts effects read (gravity torques, approach
// directions), and synthetic ground truth: a concealed effect is recovered within 3 sigma.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/effect_context.h"
#include "cellmetry/job.h"
#include "cellmetry/workcell.h"
#include "cellmetry/workcell_simulation.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

std::shared_ptr<const RobotModel> Ur3() {
  return testing::Plugins().CreateRobotModel(
      "serial_mdh", ConfigNode::LoadFile(testing::Source("configs/robots/ur3.yaml")));
}

std::unique_ptr<Effect> MakeEffect(const std::string& yaml, const RobotModel& robot) {
  const ConfigNode config = ConfigNode::LoadString(yaml, "test");
  return testing::Plugins().CreateEffect(config["type"].AsString(), config, robot);
}

const std::vector<std::string>& EffectConfigs() {
  static const std::vector<std::string> configs = {
      "{type: joint_compliance, link_masses_kg: [2, 3.4, 1.3, 0.8, 0.8, 0.35]}",
      "{type: backlash, joints: [2, 3]}",
      "{type: transmission_error, joints: [1, 4], harmonics: [1, 2, 5]}",
      "{type: joint_scale}",
      "{type: thermal_drift, reference_c: 20}",
      "{type: thermal_drift, model: warmup, time_constant_s: 600}",
      "{type: depth_bias, cameras: [cam1, cam2]}",
      "{type: detection_bias, cameras: [cam2], targets: [world, tool], frame: target}",
      "{type: detection_bias, cameras: [cam1, cam2], targets: [tool]}",
  };
  return configs;
}

// A sample in the middle of a run: moved into from both sides, warm, on cam2.
struct ContextFixture {
  std::vector<double> q = {0.3, -1.2, 1.1, -0.7, 1.4, 0.2};
  std::vector<int> approach = {1, -1, 1, 1, -1, -1};
  std::vector<Pose> frames;
  EffectContext context;
  explicit ContextFixture(const RobotModel& robot) {
    std::vector<double> nominal;
    for (const auto& p : robot.parameters()) nominal.push_back(p.nominal);
    robot.JointFrames(q.data(), nominal.data(), &frames);
    context.num_joints = 6;
    context.q = q.data();
    context.approach = approach.data();
    context.T_base_joint = &frames;
    context.time_s = 900;
    context.temperature_c = 27.5;
    context.payload_kg = 0.5;
    context.camera = "cam2";
    context.target = "tool";
  }
};

// The stage's values before the effect: joint errors, or a position (and, for measurements, the
// target's rotation after it, column-major: a turn about (1, 2, 3)).
std::vector<double> Untouched(const Effect& effect) {
  if (effect.stage() == EffectStage::kJoint) return std::vector<double>(6, 0.0);
  std::vector<double> values = {120.0, -80.0, 650.0};
  if (effect.stage() == EffectStage::kMeasurement) {
    const Eigen::Matrix3d R = RotationFromRvec(Eigen::Vector3d(0.1, 0.2, 0.3).data());
    values.insert(values.end(), R.data(), R.data() + 9);
  }
  return values;
}

std::vector<double> Values(const Effect& effect, const EffectContext& context,
                           const std::vector<double>& params) {
  std::vector<double> values = Untouched(effect);
  effect.Apply(context, params.data(), values.data());
  return values;
}

TEST(Effects, JetDerivativesMatchCentralDifferences) {
  const auto ur3 = Ur3();
  const ContextFixture fixture(*ur3);
  std::mt19937 rng(5);
  for (const auto& yaml : EffectConfigs()) {
    SCOPED_TRACE(yaml);
    const auto effect = MakeEffect(yaml, *ur3);
    const size_t n = effect->parameters().size();
    ASSERT_LE(n, size_t(kJetStride) * 4);
    std::vector<double> params(n);
    for (auto& p : params) p = std::uniform_real_distribution<double>(-1e-3, 1e-3)(rng);
    const std::vector<double> base = Values(*effect, fixture.context, params);
    for (size_t k = 0; k < n; ++k) {
      // Jet with a unit derivative on parameter k.
      std::vector<Jet> jets(n);
      for (size_t i = 0; i < n; ++i) jets[i] = Jet(params[i]);
      jets[k].v[0] = 1.0;
      std::vector<Jet> values;
      for (double v : Untouched(*effect)) values.push_back(Jet(v));
      effect->Apply(fixture.context, jets.data(), values.data());
      const double h = 1e-7;
      std::vector<double> plus = params, minus = params;
      plus[k] += h, minus[k] -= h;
      const auto up = Values(*effect, fixture.context, plus);
      const auto down = Values(*effect, fixture.context, minus);
      for (size_t i = 0; i < base.size(); ++i) {
        EXPECT_NEAR(values[i].a, base[i], 1e-12);
        const double numeric = (up[i] - down[i]) / (2 * h);
        EXPECT_NEAR(values[i].v[0], numeric, 1e-6 * (1 + std::abs(numeric)))
            << effect->parameters()[k].name << " -> value " << i;
      }
    }
  }
}

TEST(Effects, ZeroParametersAreNoEffect) {
  const auto ur3 = Ur3();
  const ContextFixture fixture(*ur3);
  for (const auto& yaml : EffectConfigs()) {
    SCOPED_TRACE(yaml);
    const auto effect = MakeEffect(yaml, *ur3);
    const std::vector<double> zero(effect->parameters().size(), 0.0);
    EXPECT_EQ(Values(*effect, fixture.context, zero), Untouched(*effect));
    EXPECT_FALSE(effect->Describe(zero).empty());
  }
}

TEST(Effects, GravityTorqueOfAHorizontalArmIsMassTimesLever) {
  // Joint 1 turns about the vertical, joint 2 about a horizontal axis (y); the arm reaches 400 mm
  // along x to the flange. Link 2 (2 kg) sits at 200 mm, a 1 kg payload at 400 mm.
  std::vector<Pose> frames(3, Pose::Identity());
  frames[1].R = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();  // z = +y
  frames[2].t = Eigen::Vector3d(400, 0, 0);
  const auto torque = GravityTorques(frames, {0.0, 2.0}, 1.0, Eigen::Vector3d(0, 0, -9.81));
  ASSERT_EQ(torque.size(), 2u);
  EXPECT_NEAR(torque[0], 0.0, 1e-12);  // a vertical axis carries no gravity torque
  // r x F about +y: (0.2 m x) x (-19.62 N z) = +3.924 N m along y; the payload adds 3.924 more.
  EXPECT_NEAR(torque[1], 2.0 * 9.81 * 0.2 + 1.0 * 9.81 * 0.4, 1e-9);
}

// A robot with two joints and no geometry: only its joint count matters here.
class TwoJoints : public RobotModelFromTemplate<TwoJoints> {
 public:
  int num_joints() const override { return 2; }
  const std::vector<Parameter>& parameters() const override { return params_; }
  template <typename T>
  bool ForwardT(const double*, const T*, Transform<T>*) const { return true; }

 private:
  std::vector<Parameter> params_;
};

TEST(EffectContext, ApproachDirectionFollowsCaptureOrderAndSurvivesRepeats) {
  Recording recording;
  for (const auto& q : std::vector<std::vector<double>>{{0, 0}, {1, 0}, {1, 0}, {0.5, 2}}) {
    Sample s;
    s.id = static_cast<int>(recording.samples.size());
    s.robot = "arm";
    s.q = q;
    recording.samples.push_back(s);
  }
  const TwoJoints model;
  const auto facts = GatherSampleFacts(recording, "arm", model, {});
  EXPECT_EQ(facts[0].approach, (std::vector<int>{0, 0}));   // nothing moved yet
  EXPECT_EQ(facts[1].approach, (std::vector<int>{1, 0}));
  EXPECT_EQ(facts[2].approach, (std::vector<int>{1, 0}));   // a repeat keeps its direction
  EXPECT_EQ(facts[3].approach, (std::vector<int>{-1, 1}));
  EXPECT_EQ(MissingFacts({.approach = true}, facts), "");  // joint 1 went up, then down
  const std::vector<SampleFacts> one_way(facts.begin(), facts.begin() + 3);
  EXPECT_EQ(MissingFacts({.approach = true}, one_way), "moves into poses from both directions");
  EXPECT_THAT(MissingFacts({.joint_frames = true}, facts), ::testing::HasSubstr("joint frames"));
}

// Synthetic ground truth: the UR3 on the simulation-B path with a concealed effect; the
// identification with that effect in the chain recovers it within 3 sigma.
void ExpectRecovered(const std::string& robot_effects, const std::string& camera_effects,
                     const std::string& job_effects, const std::string& job_camera_effects) {
  const std::string dir = testing::TempDirForThisTest("effects");
  std::string sim = testing::ReadText(testing::Source("configs/simulations/ur3_two_cameras.yaml"));
  sim = testing::ReplaceOnce(sim, "../robots/ur3.yaml", testing::Source("configs/robots/ur3.yaml"));
  sim = testing::ReplaceOnce(sim, "../../tests/data/vsb/sim_b", testing::Source("tests/data/vsb/sim_b"));
  sim = testing::ReplaceOnce(sim, "    poses:", "    effects: " + robot_effects + "\n    poses:");
  sim += camera_effects.empty() ? "" : "effects: " + camera_effects + "\n";
  testing::WriteText(dir + "/sim.yaml", sim);
  const WorkcellSimulationSpec spec = LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins());
  WorkcellTruth truth;
  const Recording recording = SimulateWorkcell(spec, &truth);
  WriteRecording(recording, dir + "/rec", TruthYaml(truth));

  std::string job = "job: workcell\nrecording: " + dir + "/rec\nuse_tool_rotation: true\n"
                    "robots:\n  ur3:\n    model: " + testing::Source("configs/robots/ur3.yaml") +
                    "\n    base: {free: all}\n    tools:\n      tool: {free: all}\n"
                    "    effects: " + job_effects + "\n";
  if (!job_camera_effects.empty()) job += "effects: " + job_camera_effects + "\n";
  job += "noise: {cameras: {cam1: {position_mm: [0.1, 0.1, 0.4], rotation_rad: [0.0005, 0.0005, 0.001]},"
         " cam2: {position_mm: [0.1, 0.1, 0.4], rotation_rad: [0.0005, 0.0005, 0.001]}}}\n"
         "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n";
  testing::WriteText(dir + "/job.yaml", job);
  const WorkcellJob loaded = LoadWorkcellJob(dir + "/job.yaml", testing::Plugins());
  const SolverMaker make_solver = [&] {
    return testing::Plugins().CreateSolver(loaded.solver_type, *loaded.solver_config);
  };
  const WorkcellResult result =
      IdentifyWorkcell(loaded.problem, ReadRecording(dir + "/rec"), make_solver);
  int checked = 0;
  for (const auto& p : result.model_parameters) {
    const auto it = truth.model.find(p.name);
    if (it == truth.model.end() || p.held) continue;
    EXPECT_LT(std::abs(p.value - it->second), 3 * p.sigma)
        << p.name << " = " << p.value << " +- " << p.sigma << ", truth " << it->second;
    EXPECT_GT(std::abs(it->second), 5 * p.sigma) << p.name << ": the effect should be clear";
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

TEST(EffectsInWorkcell, ConcealedComplianceIsRecovered) {
  const std::string compliance =
      "[{type: joint_compliance, joints: [2, 3], link_masses_kg: [2, 3.4, 1.3, 0.8, 0.8, 0.35]}]";
  ExpectRecovered("[{effect: " + compliance.substr(1, compliance.size() - 2) +
                      ", values: {j2.compliance: 1.5e-4, j3.compliance: -8e-5}}]",
                  "", compliance, "");
}

TEST(EffectsInWorkcell, ConcealedDepthBiasIsRecovered) {
  ExpectRecovered("[]",
                  "[{effect: {type: depth_bias, cameras: [cam1], terms: [scale]}, "
                  "values: {cam1.depth_scale: 2.0e-3}}]",
                  "[]", "[{type: depth_bias, cameras: [cam1], terms: [scale]}]");
}

}  // namespace
}  // namespace cellmetry
