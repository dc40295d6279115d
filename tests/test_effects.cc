// The effect library (plugins/effects) and its place in the workcell identification: exact
// derivatives, "zero is no effect", the facts effects read (gravity torques, approach
// directions), and synthetic ground truth: a concealed effect is recovered within 3 sigma.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <random>

#include "cellmetry/cell/job.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/model/effect_context.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

std::shared_ptr<const RobotModel> Ur3() {
  return testing::Plugins().CreateRobotModel(
      "serial_mdh", ConfigNode::LoadFile(testing::Source("configs/robots/ur3_vsb2020.yaml")));
}

std::shared_ptr<const RobotModel> Delta() {
  return testing::Plugins().CreateRobotModel(
      "delta", ConfigNode::LoadFile(testing::Source("configs/robots/delta.yaml")));
}

std::unique_ptr<Effect> MakeEffect(const std::string& yaml, const RobotModel& robot) {
  const ConfigNode config = ConfigNode::LoadString(yaml, "test");
  return testing::Plugins().CreateEffect(config["type"].AsString(), config, robot);
}

const std::vector<std::string>& EffectConfigs() {
  static const std::vector<std::string> configs = {
      "{type: joint_compliance, link_masses_kg: [2, 3.4, 1.3, 0.8, 0.8, 0.35]}",
      "{type: backlash, joints: [2, 3]}",
      "{type: backlash, joints: [2, 3], held_by: gravity, link_masses_kg: [2, 3, 1, 1, 1, 0.3]}",
      "{type: transmission_error, joints: [1, 4], harmonics: [1, 2, 5]}",
      "{type: joint_scale}",
      "{type: joint_coupling, joints: [5, 6], from: 4}",
      "{type: link_bending, links: [2, 3], link_masses_kg: [2, 3.4, 1.3, 0.8, 0.8, 0.35]}",
      "{type: base_tilt, pivot_mm: 300, link_masses_kg: [2, 3.4, 1.3, 0.8, 0.8, 0.35]}",
      "{type: thermal_drift, reference_c: 20}",
      "{type: thermal_drift, model: warmup, time_constant_s: 600}",
      "{type: depth_bias, cameras: [cam1, cam2]}",
      "{type: depth_bias, cameras: [cam2], terms: [scale, tilt]}",
      "{type: detection_bias, cameras: [cam2], targets: [world, tool], frame: target}",
      "{type: detection_bias, cameras: [cam1, cam2], targets: [tool]}",
      "{type: target_scale, targets: [world, tool]}",
      "{type: target_scale, targets: [world, tool], shared: true}",
      "{type: camera_intrinsics, cameras: [cam1, cam2]}",
      "{type: camera_intrinsics, cameras: [cam2], terms: [focal]}",
      "{type: camera_intrinsics, cameras: [cam2], terms: [principal, radial]}",
      "{type: camera_intrinsics, cameras: [cam2], terms: [radial, k2, tangential]}",
      "{type: camera_intrinsics, cameras: [cam1, cam2], "
      "terms: [focal, principal, radial, k2, tangential]}",
      "{type: target_tilt, targets: [tool]}",
      "{type: world_frame, target: tool}",
      "{type: world_frame, target: tool, axes: [x, y, z]}",
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

// The stage's values before the effect: joint errors, or a position and the rotation after it
// (the flange's or the measured target's, column-major: a turn about (1, 2, 3)).
std::vector<double> Untouched(const Effect& effect) {
  if (effect.stage() == EffectStage::kJoint) return std::vector<double>(6, 0.0);
  std::vector<double> values = {120.0, -80.0, 650.0};
  const Eigen::Matrix3d R = RotationFromRvec(Eigen::Vector3d(0.1, 0.2, 0.3).data());
  values.insert(values.end(), R.data(), R.data() + 9);
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

// Every effect says how large its physics usually is, so that a report can flag a finding far
// beyond it; a prior-carrying nuisance (detection_bias) has its prior instead.
TEST(Effects, EveryParameterHasAPlausibleSizeOrAPrior) {
  const auto ur3 = Ur3();
  for (const auto& yaml : EffectConfigs()) {
    SCOPED_TRACE(yaml);
    // Held in a variable: a range-for over a temporary's member dangles (AddressSanitizer).
    const auto effect = MakeEffect(yaml, *ur3);
    for (const auto& p : effect->parameters()) {
      EXPECT_TRUE(p.plausible.has_value() != p.prior_sigma.has_value()) << p.name;
      if (p.plausible) {
        EXPECT_GT(*p.plausible, 0.0) << p.name;
      }
    }
  }
  const auto delta = Delta();
  for (const std::string yaml : {"{type: platform_tilt}", "{type: ball_joint_clearance}"}) {
    const auto effect = MakeEffect(yaml, *delta);
    for (const auto& p : effect->parameters()) EXPECT_TRUE(p.plausible) << p.name;
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

// The camera-side effects do what their physics says to a measured pose.
std::vector<double> Measured(const std::string& yaml, const std::vector<double>& params,
                             const std::string& target = "tool") {
  const auto robot = Ur3();
  const auto effect = MakeEffect(yaml, *robot);
  ContextFixture fixture(*robot);
  fixture.context.target = target;
  std::vector<double> values = Untouched(*effect);
  effect->Apply(fixture.context, params.data(), values.data());
  return values;
}

TEST(CameraEffects, TargetScaleScalesEveryCoordinateOfThatTargetOnly) {
  const auto v = Measured("{type: target_scale, targets: [tool]}", {0.01});
  EXPECT_NEAR(v[0], 120.0 * 1.01, 1e-9);
  EXPECT_NEAR(v[1], -80.0 * 1.01, 1e-9);
  EXPECT_NEAR(v[2], 650.0 * 1.01, 1e-9);
  EXPECT_NEAR(Measured("{type: target_scale, targets: [tool]}", {0.01}, "world")[2], 650.0, 1e-12);
}

TEST(CameraEffects, FocalLengthScalesDepthAloneAndKeepsTheRay) {
  const auto v = Measured("{type: camera_intrinsics, cameras: [cam2], terms: [focal]}", {0.02});
  EXPECT_NEAR(v[2], 650.0 * 1.02, 1e-9);
  EXPECT_NEAR(v[0] / v[2], 120.0 / 650.0, 1e-12);  // same ray
  EXPECT_NEAR(v[1] / v[2], -80.0 / 650.0, 1e-12);
}

TEST(CameraEffects, PrincipalPointTurnsTheRayAndTheMeasuredRotation) {
  const auto v =
      Measured("{type: camera_intrinsics, cameras: [cam2], terms: [principal]}", {0.01, -0.005});
  EXPECT_NEAR(v[0] / v[2], 120.0 / 650.0 - 0.01, 1e-12);
  EXPECT_NEAR(v[1] / v[2], -80.0 / 650.0 + 0.005, 1e-12);
  EXPECT_NEAR(v[2], 650.0, 1e-12);
  const Eigen::Matrix3d before = RotationFromRvec(Eigen::Vector3d(0.1, 0.2, 0.3).data());
  const Eigen::Matrix3d after = Eigen::Map<const Eigen::Matrix3d>(v.data() + 3);
  const Eigen::Vector3d turn = RvecFromRotation(after * before.transpose());
  EXPECT_NEAR(turn.x(), -0.005, 1e-9);  // about x by -py
  EXPECT_NEAR(turn.y(), -0.01, 1e-9);   // about y by -px
}

TEST(CameraEffects, RadialErrorVanishesOnTheAxisAndGrowsWithRadius) {
  const std::string yaml = "{type: camera_intrinsics, cameras: [cam2], terms: [radial]}";
  const auto v = Measured(yaml, {0.05});
  const double r2 = (120.0 * 120.0 + 80.0 * 80.0) / (650.0 * 650.0);
  EXPECT_NEAR(v[2], 650.0 * (1 - 2 * 0.05 * r2), 1e-9);
  EXPECT_NEAR(v[0] / v[2], 120.0 / 650.0 * (1 + 0.05 * r2), 1e-12);
}

TEST(CameraEffects, TargetTiltTurnsTheTargetAboutItsOwnAxesAndKeepsItsPosition) {
  const auto v = Measured("{type: target_tilt, targets: [tool]}", {0.02, 0.0});
  EXPECT_NEAR(v[0], 120.0, 1e-12);
  const Eigen::Matrix3d before = RotationFromRvec(Eigen::Vector3d(0.1, 0.2, 0.3).data());
  const Eigen::Matrix3d after = Eigen::Map<const Eigen::Matrix3d>(v.data() + 3);
  const Eigen::Vector3d turn = RvecFromRotation(before.transpose() * after);  // target axes
  EXPECT_NEAR(turn.x(), 0.02, 1e-12);
  EXPECT_NEAR(turn.y(), 0.0, 1e-12);
}

TEST(Effects, GravityTorqueOfAHorizontalArmIsMassTimesLever) {
  // Joint 1 turns about the vertical, joint 2 about a horizontal axis (y); the arm reaches 400 mm
  // along x to the flange. Link 2 (2 kg) sits at 200 mm, a 1 kg payload at 400 mm.
  std::vector<Pose> frames(3, Pose::Identity());
  frames[1].R =
      Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();  // z = +y
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
  bool ForwardT(const double*, const T*, Transform<T>*) const {
    return false;
  }  // no pose

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
  EXPECT_EQ(facts[0].approach, (std::vector<int>{0, 0}));  // nothing moved yet
  EXPECT_EQ(facts[1].approach, (std::vector<int>{1, 0}));
  EXPECT_EQ(facts[2].approach, (std::vector<int>{1, 0}));  // a repeat keeps its direction
  EXPECT_EQ(facts[3].approach, (std::vector<int>{-1, 1}));
  EXPECT_EQ(MissingFacts({.approach = true}, facts), "");  // joint 1 went up, then down
  const std::vector<SampleFacts> one_way(facts.begin(), facts.begin() + 3);
  EXPECT_EQ(MissingFacts({.approach = true}, one_way), "moves into poses from both directions");
  EXPECT_THAT(MissingFacts({.joint_frames = true}, facts), ::testing::HasSubstr("joint frames"));
}

// Compliance follows the load: the same pose with a payload deflects each joint by c times the
// payload's own gravity torque more.
TEST(Effects, ComplianceFollowsThePayload) {
  const auto ur3 = Ur3();
  ContextFixture fixture(*ur3);
  const auto compliance = MakeEffect("{type: joint_compliance, joints: [2, 3]}", *ur3);
  const std::vector<double> c = {2e-4, 1e-4};
  fixture.context.payload_kg = 0.0;
  const std::vector<double> empty = Values(*compliance, fixture.context, c);
  fixture.context.payload_kg = 1.5;
  const std::vector<double> loaded = Values(*compliance, fixture.context, c);
  const std::vector<double> payload_only = GravityTorques(
      fixture.frames, std::vector<double>(6, 0.0), 1.5, fixture.context.gravity_base);
  EXPECT_NEAR(loaded[1] - empty[1], c[0] * payload_only[1], 1e-15);
  EXPECT_NEAR(loaded[2] - empty[2], c[1] * payload_only[2], 1e-15);
  EXPECT_GT(std::abs(payload_only[1]), 1.0);  // N m: the pose loads joint 2
}

// A horizontal link as a cantilever: the closed form along the beam gives the textbook tip, P L^2
// / (2 E I) turned and P L^3 / (3 E I) dropped under a load P at its end, w L^3 / (6 E I) and
// w L^4 / (8 E I) under its own weight w per length; the flange turns down, about +y.
TEST(Effects, LinkBendingOfAHorizontalLinkIsTheTextbookCantilever) {
  // Joint 2 turns about +y at the origin; link 2 reaches 400 mm along x to the flange.
  std::vector<Pose> frames(3, Pose::Identity());
  frames[1].R = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  frames[2].t = Eigen::Vector3d(400, 0, 0);
  const TwoJoints model;
  const double L = 0.4, g = 9.81, c = 2e-5;  // m, m/s^2, 1/(N m^2)
  EffectContext context;
  context.num_joints = 2;
  context.T_base_joint = &frames;
  const auto bend = [&](const std::string& masses, double payload_kg) {
    context.payload_kg = payload_kg;
    const auto effect =
        MakeEffect("{type: link_bending, links: [2], link_masses_kg: " + masses + "}", model);
    std::vector<double> values = {400, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    effect->Apply(context, &c, values.data());
    const Eigen::Map<const Eigen::Matrix3d> R(values.data() + 3);
    return std::make_pair(RvecFromRotation(R),
                          Eigen::Vector3d(values[0] - 400, values[1], values[2]));
  };
  const double P = 1.5 * g;
  const auto [tip_turn, tip_move] = bend("[0, 0]", 1.5);
  EXPECT_NEAR(tip_turn.y(), c * P * L * L / 2, 1e-12);
  EXPECT_NEAR(tip_move.z(), -1e3 * c * P * L * L * L / 3, 1e-12);  // mm
  EXPECT_NEAR(tip_turn.x(), 0.0, 1e-15);
  EXPECT_NEAR(tip_move.x(), 0.0, 1e-12);
  const double w = 2.0 * g / L;
  const auto [own_turn, own_move] = bend("[0, 2]", 0.0);
  EXPECT_NEAR(own_turn.y(), c * w * L * L * L / 6, 1e-12);
  EXPECT_NEAR(own_move.z(), -1e3 * c * w * L * L * L * L / 8, 1e-12);
  // The load only on link 1 (before the bending link) bends nothing.
  const auto [none_turn, none_move] = bend("[5, 0]", 0.0);
  EXPECT_NEAR(none_turn.norm() + none_move.norm(), 0.0, 1e-15);
}

// A mounting tilting under an outstretched arm: the moment about the pivot is the load times its
// reach, the arm turns down about the pivot by c times it, so the flange drops by the turn times
// its reach and swings outward by the turn times the pivot's depth below it.
TEST(Effects, BaseTiltTurnsTheArmAboutAPivotBelowTheBase) {
  std::vector<Pose> frames(3, Pose::Identity());
  frames[1].R = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  frames[2].t = Eigen::Vector3d(400, 0, 0);
  const TwoJoints model;
  EffectContext context;
  context.num_joints = 2;
  context.T_base_joint = &frames;
  context.payload_kg = 1.5;
  const auto tilt = MakeEffect("{type: base_tilt, pivot_mm: 500, link_masses_kg: [0, 0]}", model);
  const double c = 3e-6;  // rad/(N m)
  std::vector<double> values = {400, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  tilt->Apply(context, &c, values.data());
  const double turn = c * 1.5 * 9.81 * 0.4;  // rad, about +y
  const Eigen::Map<const Eigen::Matrix3d> R(values.data() + 3);
  EXPECT_NEAR(RvecFromRotation(R).y(), turn, 1e-15);
  EXPECT_NEAR(values[2], -turn * 400, 1e-12);       // mm: down by the turn times the reach
  EXPECT_NEAR(values[0] - 400, turn * 500, 1e-12);  // and out by the turn times the depth
  EXPECT_NEAR(values[1], 0.0, 1e-15);
}

// Backlash held by gravity sits against the flank the gravity torque pushes it to, whichever way
// the joint came, and by half the play once the torque is well beyond the friction's hold; the
// approach form follows the last move instead.
TEST(Effects, BacklashHeldByGravityFollowsTheTorqueNotTheMove) {
  const auto ur3 = Ur3();
  ContextFixture fixture(*ur3);
  const auto gravity =
      MakeEffect("{type: backlash, joints: [2], held_by: gravity, hold_nm: 0.01}", *ur3);
  const auto approach = MakeEffect("{type: backlash, joints: [2]}", *ur3);
  const std::vector<double> b = {4e-3};
  const std::vector<double> torque =
      GravityTorques(fixture.frames, std::vector<double>(6, 1.0), fixture.context.payload_kg,
                     fixture.context.gravity_base);
  ASSERT_GT(std::abs(torque[1]), 1.0);  // N m, a hundred times the hold
  const double held = Values(*gravity, fixture.context, b)[1];
  EXPECT_NEAR(held, 0.5 * b[0] * (torque[1] > 0 ? 1.0 : -1.0), 1e-12);
  for (int from : {-1, 1}) {
    fixture.approach[1] = from;
    EXPECT_DOUBLE_EQ(Values(*gravity, fixture.context, b)[1], held);
    EXPECT_DOUBLE_EQ(Values(*approach, fixture.context, b)[1], -0.5 * b[0] * from);
  }
  EXPECT_THROW(MakeEffect("{type: backlash, hold_nm: 1}", *ur3), InputError);
  EXPECT_THROW(MakeEffect("{type: backlash, held_by: friction}", *ur3), InputError);
}

// A coupling turns the driven joints by k times the driving joint's reading and touches nothing
// else; a pair the arm cannot have is refused in words.
TEST(Effects, CouplingTurnsTheDrivenJointsWithTheDrivingOne) {
  const auto ur3 = Ur3();
  ContextFixture fixture(*ur3);
  const auto coupling = MakeEffect("{type: joint_coupling, joints: [5, 6], from: 4}", *ur3);
  const std::vector<double> k = {2e-3, -3e-3};
  const std::vector<double> dq = Values(*coupling, fixture.context, k);
  EXPECT_DOUBLE_EQ(dq[4], k[0] * fixture.q[3]);
  EXPECT_DOUBLE_EQ(dq[5], k[1] * fixture.q[3]);
  for (int j = 0; j < 4; ++j) EXPECT_EQ(dq[j], 0.0) << "joint " << j + 1;
  for (const auto& [yaml, words] : std::vector<std::pair<std::string, std::string>>{
           {"{type: joint_coupling, joints: [6]}", "names the driven joints and the driving one"},
           {"{type: joint_coupling, joints: [6], from: 7}", "no joint 7 on a 6-joint robot"},
           {"{type: joint_coupling, joints: [5, 6], from: 6}", "does not couple to itself"}}) {
    const InputError e = testing::CatchInputError([&] { MakeEffect(yaml, *ur3); });
    EXPECT_THAT(e.message(), ::testing::HasSubstr(words)) << yaml;
  }
}

// A simulation cycles its payloads over the poses and records them.
TEST(EffectsInWorkcell, SimulatedPayloadsCycleOverThePoses) {
  const std::string dir = testing::TempDirForThisTest("payloads");
  std::string sim = testing::ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml"));
  sim = testing::ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml",
                             testing::Source("configs/robots/ur3_vsb2020.yaml"));
  sim = testing::ReplaceOnce(sim, "payloads_kg: [0, 1.0]", "payloads_kg: [0, 1.0, 2.5]");
  testing::WriteText(dir + "/sim.yaml", sim);
  const Recording recording =
      SimulateWorkcell(LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins()), nullptr);
  WriteRecording(recording, dir + "/rec");
  const Recording read = ReadRecording(dir + "/rec");
  ASSERT_GE(read.samples.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    ASSERT_TRUE(read.samples[i].payload_kg.has_value());
    EXPECT_EQ(*read.samples[i].payload_kg,
              std::vector<double>({0, 1.0, 2.5})[read.samples[i].pose % 3]);
  }
}

// The delta arm's effects (platform_tilt, ball_joint_clearance) read its rods.

// One delta sample's facts (rods, flange Jacobian) as GatherSampleFacts gives them.
struct DeltaContext {
  SampleFacts facts;
  EffectContext context;
  DeltaContext(const RobotModel& delta, std::vector<double> q_rad, double payload_kg = 0.0) {
    Recording recording;
    recording.robots["delta"] = 3;
    Sample sample;
    sample.robot = "delta";
    sample.q = std::move(q_rad);
    sample.payload_kg = payload_kg;
    recording.samples.push_back(sample);
    std::vector<double> nominal;
    for (const auto& p : delta.parameters()) nominal.push_back(p.nominal);
    facts = GatherSampleFacts(recording, "delta", delta, nominal).at(0);
    EXPECT_EQ(facts.links.size(), 3u);
    context = ContextOf(facts, Eigen::Vector3d(0, 0, -9.81));
  }
};

// A flange pose as the flange stage's values: position, then rotation column-major.
std::vector<double> FlangeValues() {
  std::vector<double> values = {20.0, -35.0, -610.0};
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  values.insert(values.end(), R.data(), R.data() + 9);
  return values;
}

TEST(DeltaEffects, JetDerivativesMatchCentralDifferences) {
  const auto delta = Delta();
  const DeltaContext fixture(*delta, {0.2, 0.7, -0.1});
  for (const std::string yaml :
       {"{type: platform_tilt}", "{type: ball_joint_clearance, arms: [1, 3]}"}) {
    SCOPED_TRACE(yaml);
    const auto effect = MakeEffect(yaml, *delta);
    const size_t n = effect->parameters().size();
    const std::vector<double> params = {2e-3, -1e-3, 3e-3};
    auto apply = [&](const std::vector<double>& p) {
      std::vector<double> values = FlangeValues();
      effect->Apply(fixture.context, p.data(), values.data());
      return values;
    };
    for (size_t k = 0; k < n; ++k) {
      std::vector<Jet> jets(n), values;
      for (size_t i = 0; i < n; ++i) jets[i] = Jet(params[i]);
      jets[k].v[0] = 1.0;
      for (double v : FlangeValues()) values.push_back(Jet(v));
      effect->Apply(fixture.context, jets.data(), values.data());
      std::vector<double> plus(params.begin(), params.begin() + n), minus = plus;
      plus[k] += 1e-7, minus[k] -= 1e-7;
      const auto up = apply(plus), down = apply(minus);
      for (size_t i = 0; i < values.size(); ++i) {
        const double numeric = (up[i] - down[i]) / 2e-7;
        EXPECT_NEAR(values[i].v[0], numeric, 1e-6 * (1 + std::abs(numeric))) << i;
      }
    }
  }
}

// Equal skew on all three parallelograms at the symmetric pose twists the platform about the
// vertical; equal clearance lowers it straight down (the rods lengthen alike).
TEST(DeltaEffects, SymmetricArmsTwistAndLowerThePlatformAboutTheVertical) {
  const auto delta = Delta();
  const DeltaContext symmetric(*delta, {0.4, 0.4, 0.4});
  const auto tilt = MakeEffect("{type: platform_tilt}", *delta);
  std::vector<double> values = FlangeValues();
  const std::vector<double> skew = {1e-3, 1e-3, 1e-3};
  tilt->Apply(symmetric.context, skew.data(), values.data());
  const Eigen::Map<const Eigen::Matrix3d> R(values.data() + 3);
  const Eigen::Vector3d w = RvecFromRotation(R);
  EXPECT_GT(w.norm(), 1e-4);
  EXPECT_NEAR(w.head<2>().norm(), 0.0, 1e-9 * w.norm() + 1e-12) << w.transpose();
  // Each arm's constraint holds: (e_i x u_i) . w = skew_i.
  for (const auto& link : symmetric.facts.links) {
    EXPECT_NEAR(link.pair_axis.cross(link.direction).dot(w), 1e-3, 1e-9);
  }

  const auto clearance = MakeEffect("{type: ball_joint_clearance}", *delta);
  values = FlangeValues();
  const std::vector<double> play = {0.1, 0.1, 0.1};
  clearance->Apply(symmetric.context, play.data(), values.data());
  const Eigen::Vector3d moved =
      Eigen::Vector3d(values[0], values[1], values[2]) - Eigen::Vector3d(20.0, -35.0, -610.0);
  EXPECT_LT(moved.z(), 0.0);  // the platform sinks
  EXPECT_NEAR(moved.head<2>().norm(), 0.0, 1e-12);
  // The tensions' shares of the weight add up to it along the vertical.
  Eigen::Vector3d pull = Eigen::Vector3d::Zero();
  for (const auto& link : symmetric.facts.links) pull += link.direction;
  EXPECT_GT(pull.z(), 0.0);  // the rods hold the platform up
}

// A delta's motors do not carry each other: compliance acts through the load on the flange,
// tau = J^T m g, which is minus the derivative of the load's potential energy.
TEST(DeltaEffects, ComplianceTorqueIsTheFlangeLoadsVirtualWork) {
  const auto delta = Delta();
  const std::vector<double> q = {0.2, 0.7, -0.1};
  const DeltaContext fixture(*delta, q, /*payload_kg=*/0.5);
  ASSERT_EQ(fixture.facts.flange_jacobian_mm.cols(), 3);
  const std::vector<double> masses = {0.1, 0.1, 0.1};  // 0.3 kg hang on the flange with 0.5
  const std::vector<double> torque = ContextGravityTorques(fixture.context, masses);
  std::vector<double> nominal;
  for (const auto& p : delta->parameters()) nominal.push_back(p.nominal);
  for (int j = 0; j < 3; ++j) {
    std::vector<double> plus = q, minus = q;
    plus[j] += 1e-5, minus[j] -= 1e-5;
    Pose up, down;
    ASSERT_TRUE(delta->Forward(plus.data(), nominal.data(), &up));
    ASSERT_TRUE(delta->Forward(minus.data(), nominal.data(), &down));
    const double dz_m_per_rad = 1e-3 * (up.t.z() - down.t.z()) / 2e-5;
    EXPECT_NEAR(torque[j], -0.8 * 9.81 * dz_m_per_rad, 1e-6) << "motor " << j + 1;
  }
  const auto compliance =
      MakeEffect("{type: joint_compliance, link_masses_kg: [0.1, 0.1, 0.1]}", *delta);
  std::vector<double> dq(3, 0.0);
  const std::vector<double> c = {1e-3, 2e-3, 3e-3};
  compliance->Apply(fixture.context, c.data(), dq.data());
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(dq[j], c[j] * torque[j], 1e-15);
}

TEST(DeltaEffects, SerialArmIsRefusedInWords) {
  const auto ur3 = Ur3();
  try {
    MakeEffect("{type: platform_tilt}", *ur3);
    FAIL() << "a serial arm has no parallelograms";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("delta"));
  }
  const auto delta = Delta();
  EXPECT_THROW(MakeEffect("{type: ball_joint_clearance, arms: [4]}", *delta), InputError);
}

// Synthetic ground truth: the UR3 on the simulation-B path with a concealed effect; the
// identification with that effect in the chain recovers it within 3 sigma.
void ExpectRecovered(const std::string& robot_effects, const std::string& camera_effects,
                     const std::string& job_effects, const std::string& job_camera_effects) {
  const std::string dir = testing::TempDirForThisTest("effects");
  std::string sim = testing::ReadText(testing::Source("configs/simulations/ur3_two_cameras.yaml"));
  sim = testing::ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml",
                             testing::Source("configs/robots/ur3_vsb2020.yaml"));
  sim = testing::ReplaceOnce(sim, "../../tests/data/vsb/sim_b",
                             testing::Source("tests/data/vsb/sim_b"));
  sim = testing::ReplaceOnce(sim, "    poses:", "    effects: " + robot_effects + "\n    poses:");
  sim += camera_effects.empty() ? "" : "effects: " + camera_effects + "\n";
  testing::WriteText(dir + "/sim.yaml", sim);
  const WorkcellSimulationSpec spec = LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins());
  WorkcellTruth truth;
  const Recording recording = SimulateWorkcell(spec, &truth);
  WriteRecording(recording, dir + "/rec", TruthYaml(truth));

  std::string job = "job: workcell\nrecording: " + dir +
                    "/rec\nuse_tool_rotation: true\n"
                    "robots:\n  ur3:\n    model: " +
                    testing::Source("configs/robots/ur3_vsb2020.yaml") +
                    "\n    base: {free: all}\n    tools:\n      tool: {free: all}\n"
                    "    effects: " +
                    job_effects + "\n";
  if (!job_camera_effects.empty()) job += "effects: " + job_camera_effects + "\n";
  job += std::string(testing::kTwoCameraNoiseYaml) +
         "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n";
  testing::WriteText(dir + "/job.yaml", job);
  const WorkcellJob loaded = LoadWorkcellJob(dir + "/job.yaml", testing::Plugins());
  const WorkcellResult result = testing::Identify(loaded, ReadRecording(dir + "/rec"));
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

// A robot effect concealed at `values` in the simulation and fitted in the job's chain.
void ExpectRobotEffectRecovered(const std::string& effect, const std::string& values) {
  ExpectRecovered("[{effect: " + effect + ", values: " + values + "}]", "", "[" + effect + "]", "");
}

TEST(EffectsInWorkcell, ConcealedComplianceIsRecovered) {
  ExpectRobotEffectRecovered(
      "{type: joint_compliance, joints: [2, 3], link_masses_kg: [2, 3.4, 1.3, 0.8, 0.8, 0.35]}",
      "{j2.compliance: 1.5e-4, j3.compliance: -8e-5}");
}

TEST(EffectsInWorkcell, ConcealedLinkBendingIsRecovered) {
  ExpectRobotEffectRecovered(
      "{type: link_bending, links: [2, 3], link_masses_kg: [2, 3.4, 1.3, 0.8, 0.8, 0.35]}",
      "{link2.flexibility: 1.5e-3, link3.flexibility: 2e-3}");
}

TEST(EffectsInWorkcell, ConcealedBaseTiltIsRecovered) {
  ExpectRobotEffectRecovered(
      "{type: base_tilt, pivot_mm: 400, link_masses_kg: [2, 3.4, 1.3, 0.8, 0.8, 0.35]}",
      "{base.compliance: 2e-4}");
}

TEST(EffectsInWorkcell, ConcealedDepthBiasIsRecovered) {
  ExpectRecovered("[]",
                  "[{effect: {type: depth_bias, cameras: [cam1], terms: [scale]}, "
                  "values: {cam1.depth_scale: 2.0e-3}}]",
                  "[]", "[{type: depth_bias, cameras: [cam1], terms: [scale]}]");
}

}  // namespace
}  // namespace cellmetry
