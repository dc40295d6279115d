// The `urdf` robot model (plugins/robots/urdf): the TX2-90L's URDF against its modified-DH
// table, exact derivatives, conventions that leave exactly what the data determines, a
// calibration on simulation recovering perturbed joint origins, the fitted arm's exports (URDF,
// robot config), and refusals in words.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <random>

#include "cellmetry/cell/result_io.h"
#include "cellmetry/cell/truth.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/exports/exports.h"
#include "cellmetry/formats/config_node.h"
#include "support/model_derivatives.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

const char kUrdf[] = "tests/data/urdf/staubli_tx2_90l.urdf";

// A `urdf` robot config in `dir` on the URDF text `urdf`, between two links.
ConfigNode UrdfConfig(const std::string& dir, const std::string& urdf,
                      const std::string& base_link = "base_link",
                      const std::string& tip_link = "tool0") {
  testing::WriteText(dir + "/robot.urdf", urdf);
  testing::WriteText(dir + "/robot.yaml", "type: urdf\nfile: robot.urdf\nbase_link: " + base_link +
                                              "\ntip_link: " + tip_link + "\n");
  return ConfigNode::LoadFile(dir + "/robot.yaml");
}

std::unique_ptr<RobotModel> Tx2() {
  const ConfigNode config =
      ConfigNode::LoadFile(testing::Source("configs/robots/staubli_tx2_90l_urdf.yaml"));
  return testing::Plugins().CreateRobotModel("urdf", config);
}

std::unique_ptr<RobotModel> Tx90lMdh() {
  const ConfigNode config =
      ConfigNode::LoadFile(testing::Source("configs/robots/staubli_tx90l.yaml"));
  return testing::Plugins().CreateRobotModel("serial_mdh", config);
}

std::vector<double> Nominal(const RobotModel& model) {
  std::vector<double> values;
  for (const auto& p : model.parameters()) values.push_back(p.nominal);
  return values;
}

std::vector<double> RandomJoints(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::vector<double> q(6);
  for (double& v : q) v = angle(rng);
  return q;
}

// base_link -> tool0 of the URDF is the MDH table's base -> flange behind the URDF's `base`
// frame, 478 mm up: the same arm at any joint vector.
void ExpectSameArmAsTheMdhTable(const RobotModel& urdf) {
  const auto mdh = Tx90lMdh();
  const std::vector<double> urdf_nominal = Nominal(urdf), mdh_nominal = Nominal(*mdh);
  const Pose T_base_link_base{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 478)};
  std::mt19937 rng(5);
  double worst_mm = 0.0, worst_rotation = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<double> q = RandomJoints(rng);
    Pose from_urdf, from_mdh;
    ASSERT_TRUE(urdf.Forward(q.data(), urdf_nominal.data(), &from_urdf));
    ASSERT_TRUE(mdh->Forward(q.data(), mdh_nominal.data(), &from_mdh));
    from_mdh = T_base_link_base * from_mdh;
    worst_mm = std::max(worst_mm, (from_urdf.t - from_mdh.t).norm());
    worst_rotation = std::max(worst_rotation, (from_urdf.R - from_mdh.R).norm());
  }
  EXPECT_LT(worst_mm, 1e-9);
  EXPECT_LT(worst_rotation, 1e-12);
  std::printf("worst flange difference: %.3g mm, %.3g in R\n", worst_mm, worst_rotation);
}

TEST(UrdfRobot, Tx2_90lUrdfIsTheModifiedDhTablesArm) {
  const auto model = Tx2();
  ASSERT_EQ(model->num_joints(), 6);
  ExpectSameArmAsTheMdhTable(*model);
}

// The TX2-90L's URDF with joint 3 hung below a fixed mount that is shifted and turned 90 deg
// about x; joint 3's origin turns it back, so the axis is y as before: the same arm.
std::string Tx2Folded() {
  std::string urdf = testing::ReadText(testing::Source(kUrdf));
  urdf = testing::ReplaceOnce(urdf, "<link name=\"link_3\"/>",
                              "<link name=\"link_3\"/>\n  <link name=\"mount\"/>\n"
                              "  <joint name=\"link_2-mount\" type=\"fixed\">\n"
                              "    <parent link=\"link_2\"/>\n    <child link=\"mount\"/>\n"
                              "    <origin xyz=\"0 0.050 0.500\" rpy=\"1.5707963267948966 0 0\"/>\n"
                              "  </joint>");
  urdf = testing::ReplaceOnce(urdf,
                              "<parent link=\"link_2\"/>\n    <child link=\"link_3\"/>\n"
                              "    <origin xyz=\"0 0.050 0.500\" rpy=\"0 0 0\"/>",
                              "<parent link=\"mount\"/>\n    <child link=\"link_3\"/>\n"
                              "    <origin xyz=\"0 0 0\" rpy=\"-1.5707963267948966 0 0\"/>");
  return urdf;
}

// Fixed joints fold into the next movable joint's origin, and an <origin rpy> turns the joint
// frame its axis is written in.
TEST(UrdfRobot, FixedJointsAndTurnedOriginsFoldIntoTheSameArm) {
  const std::string dir = testing::TempDirForThisTest("urdf_robot");
  const auto model = testing::Plugins().CreateRobotModel("urdf", UrdfConfig(dir, Tx2Folded()));
  ASSERT_EQ(model->num_joints(), 6);
  ExpectSameArmAsTheMdhTable(*model);
}

TEST(UrdfRobot, ParametersAreTheJointOriginsNamedAfterTheUrdfsJoints) {
  const auto model = Tx2();
  const auto& p = model->parameters();
  ASSERT_EQ(p.size(), 42u);
  const std::vector<std::string> joint_3 = {"joint_3.x",     "joint_3.y",     "joint_3.z",
                                            "joint_3.roll",  "joint_3.pitch", "joint_3.yaw",
                                            "joint_3.offset"};
  for (size_t k = 0; k < joint_3.size(); ++k) EXPECT_EQ(p[14 + k].name, joint_3[k]);
  EXPECT_EQ(p[14 + 1].unit, "mm");
  EXPECT_NEAR(p[14 + 1].nominal, 50.0, 1e-12);  // the URDF's 0.050 m
  EXPECT_NEAR(p[14 + 2].nominal, 500.0, 1e-12);
  EXPECT_EQ(p[14 + 3].unit, "rad");
  EXPECT_EQ(model->JointOffsetParameter(2), 20);
}

// Held by convention: joint 1's seven put the base frame; per joint, a turn about its own axis
// (the offset's), a shift along and a turn about the previous axis; where joints 2 and 3 are
// parallel, where joint 3's axis stands about joint 2's; joint 6's offset and shift along z put
// the flange. 18 left free, as many as the MDH table frees.
TEST(UrdfRobot, ConventionsHoldWhatTheBaseToolAndNeighbouringJointsCarry) {
  const auto model = Tx2();
  std::vector<std::string> held;
  int free = 0;
  for (const Parameter& p : model->parameters()) {
    if (p.convention.empty())
      ++free;
    else
      held.push_back(p.name);
  }
  const std::vector<std::string> expected = {
      "joint_1.x",   "joint_1.y",      "joint_1.z",     "joint_1.roll",  "joint_1.pitch",
      "joint_1.yaw", "joint_1.offset", "joint_2.z",     "joint_2.pitch", "joint_2.yaw",
      "joint_3.x",   "joint_3.y",      "joint_3.pitch", "joint_4.y",     "joint_4.pitch",
      "joint_4.yaw", "joint_5.z",      "joint_5.pitch", "joint_5.yaw",   "joint_6.y",
      "joint_6.z",   "joint_6.pitch",  "joint_6.yaw",   "joint_6.offset"};
  EXPECT_EQ(held, expected);
  EXPECT_EQ(free, 18);
  const auto& p = model->parameters();
  EXPECT_THAT(p[FindParameter(p, "joint_3.x")].convention, HasSubstr("parallel axis of joint_2"));
}

// One joint: its seven parameters put the base frame, all held; it turns the tip about z.
TEST(UrdfRobot, AChainOfOneJointIsHeldWhole) {
  const std::string dir = testing::TempDirForThisTest("urdf_robot");
  const auto model = testing::Plugins().CreateRobotModel(
      "urdf", UrdfConfig(dir, testing::ReadText(testing::Source(kUrdf)), "base_link", "link_1"));
  ASSERT_EQ(model->num_joints(), 1);
  for (const Parameter& p : model->parameters()) EXPECT_FALSE(p.convention.empty()) << p.name;
  const double q = 0.5;
  Pose T;
  ASSERT_TRUE(model->Forward(&q, Nominal(*model).data(), &T));
  EXPECT_LT((T.t - Eigen::Vector3d(0, 0, 478)).norm(), 1e-12);
  EXPECT_NEAR(T.R(1, 0), std::sin(q), 1e-15);
}

// Column k: how the tool point and its rotation move with parameter k of [model, base, tool],
// stacked over poses, each column scaled to unit length (mm and rad alike).
Eigen::MatrixXd CellJacobian(const RobotModel& model, const std::vector<double>& params,
                             int poses) {
  const int n = static_cast<int>(params.size());
  const Eigen::Vector3d tool_mm(20, -10, 150);
  Eigen::MatrixXd J(6 * poses, n + 12);
  std::mt19937 rng(9);
  for (int s = 0; s < poses; ++s) {
    const std::vector<double> q = RandomJoints(rng);
    Pose flange;
    Eigen::Matrix<double, 6, Eigen::Dynamic> twists;
    EXPECT_TRUE(model.ForwardWithTwists(q.data(), params.data(), &flange, &twists));
    const Eigen::Vector3d tool = flange * tool_mm;
    auto rows = J.middleRows(6 * s, 6);
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d w = twists.col(k).tail<3>();
      rows.col(k) << twists.col(k).head<3>() + w.cross(tool - flange.t), w;
    }
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector3d e = Eigen::Vector3d::Unit(a), e_flange = flange.R.col(a);
      rows.col(n + a) << e, Eigen::Vector3d::Zero();             // base shift
      rows.col(n + 3 + a) << e.cross(tool), e;                   // base turn
      rows.col(n + 6 + a) << e_flange, Eigen::Vector3d::Zero();  // tool shift
      rows.col(n + 9 + a) << Eigen::Vector3d::Zero(), e_flange;  // tool turn
    }
  }
  for (int c = 0; c < J.cols(); ++c) J.col(c).normalize();
  return J;
}

int Rank(const Eigen::MatrixXd& J) {
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(J).singularValues();
  int rank = 0;
  for (int i = 0; i < s.size(); ++i) rank += s[i] > 1e-9 * s[0] ? 1 : 0;
  return rank;
}

// The free parameters, base and tool are independent (the data determines them), and every
// held one moves the tool as some combination of them does (the data could not tell it apart):
// the conventions are exactly the redundancies, at the nominal geometry and off it.
void ExpectConventionsAreExactlyTheRedundancies(const RobotModel& model) {
  const auto& p = model.parameters();
  std::vector<double> params = Nominal(model);
  std::mt19937 rng(4);
  std::normal_distribution<double> nudge(0.0, 1e-3);
  for (int variant = 0; variant < 2; ++variant) {
    const Eigen::MatrixXd J = CellJacobian(model, params, 40);
    std::vector<int> free_columns;
    for (int k = 0; k < static_cast<int>(p.size()); ++k) {
      if (p[k].convention.empty()) free_columns.push_back(k);
    }
    for (int c = static_cast<int>(p.size()); c < J.cols(); ++c) free_columns.push_back(c);
    Eigen::MatrixXd free(J.rows(), free_columns.size());
    for (size_t c = 0; c < free_columns.size(); ++c) free.col(c) = J.col(free_columns[c]);
    EXPECT_EQ(Rank(free), 30) << "variant " << variant;
    for (int k = 0; k < static_cast<int>(p.size()); ++k) {
      if (p[k].convention.empty()) continue;
      Eigen::MatrixXd with(J.rows(), free.cols() + 1);
      with << free, J.col(k);
      EXPECT_EQ(Rank(with), 30) << p[k].name << ", variant " << variant;
    }
    for (double& v : params) v += nudge(rng);  // off the URDF's geometry: the same
  }
}

TEST(UrdfRobot, FreeParametersAreIndependentAndEveryHeldOneIsRedundant) {
  ExpectConventionsAreExactlyTheRedundancies(*Tx2());
  // Joint 3 below a turned fixed mount: its parameters are written in the mount's axes.
  const std::string dir = testing::TempDirForThisTest("urdf_robot");
  const auto folded = testing::Plugins().CreateRobotModel("urdf", UrdfConfig(dir, Tx2Folded()));
  ExpectConventionsAreExactlyTheRedundancies(*folded);
}

// Every parameter's derivative, from the Jet overload, against central differences, at random
// joints and a perturbed geometry; and the flange twists (ForwardWithTwists, on Jets).
TEST(UrdfRobot, JetDerivativesMatchCentralDifferences) {
  const auto model = Tx2();
  const int n = static_cast<int>(model->parameters().size());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> nudge(-0.05, 0.05);
  for (int trial = 0; trial < 5; ++trial) {
    const std::vector<double> q = RandomJoints(rng);
    std::vector<double> params = Nominal(*model);
    for (double& v : params) v += nudge(rng);
    Pose T_twists;
    Eigen::Matrix<double, 6, Eigen::Dynamic> twists;
    ASSERT_TRUE(model->ForwardWithTwists(q.data(), params.data(), &T_twists, &twists));
    for (int k = 0; k < n; ++k) {
      Transform<Jet> T_jet;
      ASSERT_TRUE(testing::JetByParameter(*model, q, params, k, &T_jet));
      const testing::CentralDifference d =
          testing::CentralDifferenceByParameter(*model, q, params, k);
      const std::string& name = model->parameters()[k].name;
      for (int r = 0; r < 3; ++r) {
        EXPECT_NEAR(T_jet.t[r].v[0], d.dt[r], 1e-6 * (1 + std::abs(d.dt[r]))) << name;
        EXPECT_NEAR(twists(r, k), d.dt[r], 1e-6 * (1 + std::abs(d.dt[r]))) << name;
        EXPECT_NEAR(twists(3 + r, k), d.w[r], 1e-6 * (1 + std::abs(d.w[r]))) << name;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(T_jet.R(r, c).v[0], d.dR(r, c), 1e-6) << name;
      }
    }
  }
}

// The joint frames (z along each axis, origin on it) and the revolute chain for exports agree
// with the forward kinematics: turning joint i moves the flange about frame i's z axis, and the
// chain's flange is the model's at any joint vector.
TEST(UrdfRobot, JointFramesAndSerialChainAgreeWithTheForwardKinematics) {
  const auto model = Tx2();
  std::vector<double> params = Nominal(*model);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> nudge(-0.02, 0.02);
  for (double& v : params) v += nudge(rng);
  SerialChain chain;
  ASSERT_TRUE(model->AsSerialChain(params.data(), &chain));
  for (int trial = 0; trial < 10; ++trial) {
    const std::vector<double> q = RandomJoints(rng);
    Pose T;
    ASSERT_TRUE(model->Forward(q.data(), params.data(), &T));
    const Pose from_chain = ChainFlangePose(chain, q.data());
    EXPECT_LT((from_chain.t - T.t).norm(), 1e-9);
    EXPECT_LT((from_chain.R - T.R).norm(), 1e-12);
    std::vector<Pose> frames;
    ASSERT_TRUE(model->JointFrames(q.data(), params.data(), &frames));
    ASSERT_EQ(frames.size(), 7u);
    EXPECT_LT((frames[6].t - T.t).norm(), 1e-9);
    for (int i = 0; i < 6; ++i) {
      const double h = 1e-5;
      std::vector<double> plus = q, minus = q;
      plus[i] += h;
      minus[i] -= h;
      Pose T_plus, T_minus;
      model->Forward(plus.data(), params.data(), &T_plus);
      model->Forward(minus.data(), params.data(), &T_minus);
      const Eigen::Vector3d z = frames[i].R.col(2);
      const Eigen::Vector3d expected = z.cross(T.t - frames[i].t);
      EXPECT_LT(((T_plus.t - T_minus.t) / (2 * h) - expected).norm(), 1e-6) << "joint " << i + 1;
    }
  }
}

// A TX2-90L whose joint origins are off the URDF's by tenths of a millimetre and milliradians
// (the free parameters), seen by two cameras, fitted by a job with `free_model: all`; the result
// written as `cellmetry run` writes it. Computed once per process for the tests below.
struct FittedTx2 {
  std::string dir;
  WorkcellSimulationSpec spec;
  WorkcellTruth truth;
  WorkcellResult result;
};

const FittedTx2& Fitted() {
  static const FittedTx2 fitted = [] {
    FittedTx2 f;
    // One folder per test: ctest runs each test as a process of its own, side by side.
    f.dir = testing::TempDirForThisTest("urdf_robot/fitted_tx2");
    const std::string& dir = f.dir;
    const std::string robot = testing::Source("configs/robots/staubli_tx2_90l_urdf.yaml");
    testing::WriteText(
        dir + "/sim.yaml",
        "simulation: workcell\nseed: 21\nrobots:\n  tx2:\n    model: " + robot +
            "\n    base: {xyz: [431, 555, -900], rvec: [0.002, -0.001, 0.003]}\n"
            "    model_errors: {joint_2.x: 0.3, joint_2.y: -0.2, joint_2.roll: 0.001,"
            " joint_2.offset: 0.002, joint_3.z: -0.4, joint_3.roll: -0.0008,"
            " joint_3.yaw: 0.0012, joint_3.offset: -0.0015, joint_4.x: 0.25,"
            " joint_4.z: 0.3, joint_4.roll: 0.0007, joint_4.offset: 0.001,"
            " joint_5.x: -0.2, joint_5.y: 0.15, joint_5.roll: -0.0009,"
            " joint_5.offset: -0.001, joint_6.x: 0.1, joint_6.roll: 0.0006}\n"
            "    tools:\n      tool: {xyz: [0.5, -0.3, 66], rvec: [0, 0, 0]}\n"
            "    poses: {random: 80, lower: [-3.1, -2.2, -2.2, -3.1, -2.0, -3.1],"
            " upper: [3.1, 2.2, 2.2, 3.1, 2.0, 3.1]}\n"
            "cameras:\n"
            "  cam1: {xyz: [440, 404, 811], rvec: [1.4836, -2.6529, -0.0716]}\n"
            "  cam2: {xyz: [900, 300, 700], rvec: [2.2, -1.5, 0.3]}\n"
            "noise:\n  position_mm: [0.1, 0.1, 0.4]\n"
            "  rotation_rad: [0.0005, 0.0005, 0.001]\n");
    f.spec = LoadWorkcellSimulation(dir + "/sim.yaml", testing::Plugins());
    const Recording recording = SimulateWorkcell(f.spec, &f.truth);
    testing::WriteText(dir + "/job.yaml",
                       "job: workcell\nrecording: rec\noutput: fit\nuse_tool_rotation: true\n"
                       "robots:\n  tx2:\n    model: " +
                           robot +
                           "\n    base: {free: all}\n"
                           "    free_model: all\n"
                           "    tools:\n      tool: {xyz: [0, 0, 60], free: all}\n" +
                           std::string(testing::kTwoCameraNoiseYaml) +
                           "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n");
    const WorkcellJob job = LoadWorkcellJob(dir + "/job.yaml", testing::Plugins(), false);
    f.result = testing::Identify(job, recording);
    WriteWorkcellResult(f.result, dir + "/fit");
    return f;
  }();
  return fitted;
}

// Every model parameter within 3 sigma of the truth, and exactly the conventions held.
TEST(UrdfRobot, CalibrationRecoversPerturbedJointOriginsWithinThreeSigma) {
  const FittedTx2& f = Fitted();
  const WorkcellResult& result = f.result;
  const WorkcellTruth& truth = f.truth;
  const WorkcellSimulationSpec& spec = f.spec;
  std::vector<std::string> held, conventions;
  for (const auto& u : result.unidentifiable) held.push_back(u.name);
  for (const Parameter& p : spec.robots[0].model->parameters()) {
    if (!p.convention.empty()) conventions.push_back("tx2.model." + p.name);
  }
  std::sort(held.begin(), held.end());
  std::sort(conventions.begin(), conventions.end());
  EXPECT_EQ(held, conventions);

  // A free parameter that moves with a held one (joint 2's offset with its pitch) is scored as
  // the combination the data determines; every other one alone.
  const WorkcellEvaluation e = EvaluateWorkcell(WorkcellResultJson(result), truth, "truth");
  int free_parameters = 0, scored = 0;
  double worst_normalized = 0.0;
  for (const auto& q : e.quantities) {
    if (q.name.rfind("tx2.model.", 0) != 0) continue;
    if (!q.combination) ++free_parameters;
    if (q.in_gauge) continue;
    ++scored;
    worst_normalized = std::max(worst_normalized, std::abs(q.normalized()));
    EXPECT_LT(std::abs(q.normalized()), 3.0)
        << q.name << " error " << q.error << " sigma " << q.sigma;
  }
  EXPECT_EQ(free_parameters, 18);
  std::printf("worst model error: %.2f sigma over %d parameters and combinations\n",
              worst_normalized, scored);
}

// The fitted arm exported: as a URDF that urdfdom reads (the export checks its chain against the
// model's forward kinematics), and as a `urdf` robot config on the same URDF whose `calibrated:`
// values rebuild the fit bit for bit, for the next job.
TEST(UrdfRobot, TheFittedArmIsExportedAsUrdfAndAsARobotConfig) {
  const Registry& registry = testing::Plugins();
  const CalibratedCell cell = ReadCalibratedCell(Fitted().dir + "/fit", registry);
  const std::string urdf = ExportText(cell, ExportFormat::kUrdf, "tx2", registry);
  const urdf::ModelInterfaceSharedPtr parsed = urdf::parseURDF(urdf);
  ASSERT_TRUE(parsed);
  int revolute = 0;
  for (const auto& [name, joint] : parsed->joints_) {
    revolute += joint->type == urdf::Joint::REVOLUTE ? 1 : 0;  // the URDF's own, with limits
  }
  EXPECT_EQ(revolute, 6);

  const std::string config_text = ExportText(cell, ExportFormat::kRobot, "tx2", registry);
  EXPECT_THAT(config_text, HasSubstr("type: urdf\n"));
  EXPECT_THAT(config_text, HasSubstr("tests/data/urdf/staubli_tx2_90l.urdf"));
  EXPECT_THAT(config_text, HasSubstr("  joint_2.x: "));
  const auto rebuilt = registry.CreateRobotModel(
      "urdf", ConfigNode::LoadString(config_text, "exported robot config"));
  const std::vector<double> rebuilt_nominal = Nominal(*rebuilt);
  EXPECT_EQ(rebuilt_nominal, cell.robots[0].values);
  // Not the URDF's own: the fit moved them.
  EXPECT_NE(rebuilt_nominal, Nominal(*Tx2()));
}

// `link`'s pose in `from` (metres) at joint values by name, walked up through the parsed tree.
Pose LinkPose(const urdf::ModelInterface& model, const std::string& from, const std::string& link,
              const std::map<std::string, double>& q) {
  Pose T = Pose::Identity();
  for (urdf::LinkConstSharedPtr l = model.getLink(link); l && l->name != from; l = l->getParent()) {
    const urdf::Pose& o = l->parent_joint->parent_to_joint_origin_transform;
    Pose origin;
    origin.t = {o.position.x, o.position.y, o.position.z};
    origin.R = Eigen::Quaterniond(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z)
                   .toRotationMatrix();
    Pose turn;
    if (l->parent_joint->type != urdf::Joint::FIXED) {
      const urdf::Vector3& a = l->parent_joint->axis;
      turn.R = Eigen::AngleAxisd(q.at(l->parent_joint->name), Eigen::Vector3d(a.x, a.y, a.z))
                   .toRotationMatrix();
    }
    T = origin * turn * T;
  }
  return T;
}

// The fitted arm's URDF keeps the source URDF's names: every link and joint from base_link to
// tool0 (fixed ones included), the joints' types, axes and limits as read; its origins are the
// fit's, so that tool0 in base_link is the calibrated model's flange to 1e-9 m.
TEST(UrdfRobot, TheFittedArmsUrdfKeepsTheSourceNamesAxesAndLimits) {
  const Registry& registry = testing::Plugins();
  const CalibratedCell cell = ReadCalibratedCell(Fitted().dir + "/fit", registry);
  const CalibratedRobot& robot = cell.robots[0];
  const urdf::ModelInterfaceSharedPtr exported =
      urdf::parseURDF(ExportText(cell, ExportFormat::kUrdf, "tx2", registry));
  const urdf::ModelInterfaceSharedPtr source =
      urdf::parseURDF(testing::ReadText(testing::Source(kUrdf)));
  ASSERT_TRUE(exported);
  ASSERT_TRUE(source);
  EXPECT_EQ(exported->getLink("base_link")->getParent()->name, "world");
  std::vector<std::string> path;  // tool0 up to base_link, in the source
  for (urdf::LinkConstSharedPtr l = source->getLink("tool0"); l->name != "base_link";
       l = l->getParent()) {
    path.push_back(l->parent_joint->name);
    const urdf::JointConstSharedPtr got = exported->getJoint(l->parent_joint->name);
    ASSERT_TRUE(got) << l->parent_joint->name;
    EXPECT_EQ(got->parent_link_name, l->parent_joint->parent_link_name);
    EXPECT_EQ(got->child_link_name, l->name);
    EXPECT_EQ(got->type, l->parent_joint->type);
    EXPECT_NEAR(
        (Eigen::Vector3d(got->axis.x, got->axis.y, got->axis.z) -
         Eigen::Vector3d(l->parent_joint->axis.x, l->parent_joint->axis.y, l->parent_joint->axis.z)
             .normalized())
            .norm(),
        0.0, 1e-15);
    if (l->parent_joint->limits && got->type == urdf::Joint::REVOLUTE) {
      ASSERT_TRUE(got->limits);
      EXPECT_EQ(got->limits->lower, l->parent_joint->limits->lower);
      EXPECT_EQ(got->limits->upper, l->parent_joint->limits->upper);
      EXPECT_EQ(got->limits->velocity, l->parent_joint->limits->velocity);
    }
  }
  EXPECT_EQ(path.size(), 8u);  // joint_1 ... joint_6, joint_6-flange, flange-tool0
  EXPECT_EQ(exported->getLink("tool")->getParent()->name, "tool0");  // the fitted tool

  std::mt19937 rng(11);
  double worst_m = 0.0, worst_rad = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const std::vector<double> q = RandomJoints(rng);
    std::map<std::string, double> by_name;
    for (int i = 0; i < 6; ++i) by_name["joint_" + std::to_string(i + 1)] = q[i];
    Pose expected;
    ASSERT_TRUE(robot.model->Forward(q.data(), robot.values.data(), &expected));
    expected.t /= 1000.0;
    const Pose got = LinkPose(*exported, "base_link", "tool0", by_name);
    worst_m = std::max(worst_m, (got.t - expected.t).norm());
    worst_rad = std::max(worst_rad, RotationError(got.R, expected.R).norm());
  }
  std::printf("exported tool0 vs calibrated FK: %.3g m, %.3g rad\n", worst_m, worst_rad);
  EXPECT_LE(worst_m, 1e-9);
  EXPECT_LE(worst_rad, 1e-9);
}

// What a user gets wrong: each refused at the config's key with the file and what to do.
InputError Refusal(const std::string& urdf, const std::string& base_link,
                   const std::string& tip_link) {
  const std::string dir = testing::TempDirForThisTest("urdf_robot");
  const ConfigNode config = UrdfConfig(dir, urdf, base_link, tip_link);
  return testing::CatchInputError([&] { testing::Plugins().CreateRobotModel("urdf", config); });
}

TEST(UrdfRobot, BadInputIsRefusedWithWhatToDo) {
  const std::string tx2 = testing::ReadText(testing::Source(kUrdf));
  {  // A link the URDF does not have: the nearest name and the list.
    const InputError e = Refusal(tx2, "base_link", "tool_0");
    EXPECT_THAT(e.what(), HasSubstr("no link 'tool_0' in "));
    EXPECT_THAT(e.what(), HasSubstr("robot.urdf"));
    EXPECT_THAT(e.what(), HasSubstr("Did you mean 'tool0'?"));
    EXPECT_EQ(e.where().line, 4);  // tip_link's line in robot.yaml
  }
  {  // `base` is beside the arm (a child of base_link), not above it: a broken chain.
    const InputError e = Refusal(tx2, "base", "tool0");
    EXPECT_THAT(e.what(), HasSubstr("link 'tool0' is not below 'base'"));
    EXPECT_THAT(e.what(), HasSubstr("tool0 <- flange <- link_6"));
    EXPECT_THAT(e.what(), HasSubstr("<- base_link)"));
  }
  {  // A prismatic joint on the chain.
    const InputError e = Refusal(testing::ReplaceOnce(tx2, "name=\"joint_4\" type=\"revolute\"",
                                                      "name=\"joint_4\" type=\"prismatic\""),
                                 "base_link", "tool0");
    EXPECT_THAT(e.what(), HasSubstr("joint 'joint_4'"));
    EXPECT_THAT(e.what(), HasSubstr("is prismatic: the urdf robot model has revolute and "
                                    "continuous joints only"));
    EXPECT_THAT(e.what(), HasSubstr("tip_link: 'link_3'"));
  }
  {  // A joint hung from its own child: urdfdom reads it, and the walk up must not go round.
    const InputError e =
        Refusal(testing::ReplaceOnce(tx2, "<parent link=\"link_3\"/>\n    <child link=\"link_4\"/>",
                                     "<parent link=\"link_4\"/>\n    <child link=\"link_4\"/>"),
                "base_link", "tool0");
    EXPECT_THAT(e.what(), HasSubstr("form a loop: joint 'joint_4' has 'link_4' as parent"));
    EXPECT_EQ(e.where().line, 2);  // file's line in robot.yaml
  }
  {  // No movable joint between the two links.
    const InputError e = Refusal(tx2, "link_6", "tool0");
    EXPECT_THAT(e.what(), HasSubstr("no revolute or continuous joint between 'link_6' and"));
  }
  {  // Not a URDF urdfdom can read.
    const InputError e = Refusal("<robot name=\"x\"><link name=\"a\"></robot>", "a", "a");
    EXPECT_THAT(e.what(), HasSubstr("urdfdom cannot parse"));
    EXPECT_THAT(e.what(), HasSubstr("xacro"));
  }
  {  // Not UTF-8, at the byte: a Latin-1 letter, and a character cut short at the end (TinyXML
     // would read past the text for it).
    const InputError latin1 =
        Refusal("<robot name=\"x\">\n<!-- St\xE4ubli -->\n</robot>", "a", "a");
    EXPECT_THAT(latin1.what(), HasSubstr("the byte 0xE4 is not UTF-8"));
    EXPECT_THAT(latin1.what(), HasSubstr("Save the URDF as UTF-8"));
    EXPECT_THAT(latin1.where().file, HasSubstr("robot.urdf"));
    EXPECT_EQ(latin1.where().line, 2);
    EXPECT_EQ(latin1.where().column, 8);
    const std::string cut = tx2 + "<!-- \xC5";
    EXPECT_EQ(Refusal(cut, "base_link", "tool0").where().column, 6);
    const InputError nul = Refusal(std::string("<robot name=\"x\">\0</robot>", 25), "a", "a");
    EXPECT_THAT(nul.what(), HasSubstr("the byte 0x00 (NUL) has no place in a URDF"));
    EXPECT_EQ(nul.where().column, 17);
  }
  {  // A '%' outside a comment: urdfdom logs a malformed number with the value as the format,
     // and "%n" there crashed the process (fuzz_urdf). One in a comment is read as before.
    const InputError e =
        Refusal(testing::ReplaceOnce(tx2, "<origin xyz=\"0 0 0.550\"", "<origin xyz=\"0 0 %n%s\""),
                "base_link", "tool0");
    EXPECT_THAT(e.what(), HasSubstr("a '%' outside a comment"));
    EXPECT_THAT(e.what(), HasSubstr("Write the value without '%'"));
    EXPECT_GT(e.where().line, 1);
    const std::string dir = testing::TempDirForThisTest("urdf_robot");
    const ConfigNode in_comment = UrdfConfig(
        dir, testing::ReplaceOnce(tx2, "<robot", "<!-- 100% -->\n<robot"), "base_link", "tool0");
    EXPECT_NO_THROW(testing::Plugins().CreateRobotModel("urdf", in_comment));
  }
  {  // A file that is not there.
    const std::string dir = testing::TempDirForThisTest("urdf_robot");
    testing::WriteText(dir + "/robot.yaml",
                       "type: urdf\nfile: missing.urdf\nbase_link: a\ntip_link: b\n");
    const ConfigNode config = ConfigNode::LoadFile(dir + "/robot.yaml");
    const InputError e =
        testing::CatchInputError([&] { testing::Plugins().CreateRobotModel("urdf", config); });
    EXPECT_THAT(e.what(), HasSubstr("cannot read the URDF"));
    EXPECT_THAT(e.what(), HasSubstr("missing.urdf"));
    EXPECT_EQ(e.where().line, 2);
  }
  {  // A device, not a file: refused before a byte is read (/dev/zero would never end).
    const ConfigNode config = ConfigNode::LoadString(
        "type: urdf\nfile: /dev/zero\nbase_link: a\ntip_link: b\n", "robot.yaml");
    const InputError e =
        testing::CatchInputError([&] { testing::Plugins().CreateRobotModel("urdf", config); });
    EXPECT_THAT(e.what(), HasSubstr("cannot read the URDF '/dev/zero'"));
  }
  {  // A calibrated value for a parameter the chain does not have.
    const std::string dir = testing::TempDirForThisTest("urdf_robot");
    testing::WriteText(dir + "/robot.urdf", tx2);
    const ConfigNode config =
        ConfigNode::LoadString("type: urdf\nfile: " + dir +
                                   "/robot.urdf\nbase_link: base_link\ntip_link: tool0\n"
                                   "calibrated: {joint_2.xx: 50.1}\n",
                               "robot.yaml");
    const InputError e =
        testing::CatchInputError([&] { testing::Plugins().CreateRobotModel("urdf", config); });
    EXPECT_THAT(e.what(), HasSubstr("no parameter 'joint_2.xx'"));
    EXPECT_THAT(e.what(), HasSubstr("Did you mean 'joint_2.x'?"));
  }
  {  // A key it needs, left out.
    const ConfigNode config =
        ConfigNode::LoadString("type: urdf\nfile: x.urdf\nbase_link: a\n", "robot.yaml");
    const InputError e =
        testing::CatchInputError([&] { testing::Plugins().CreateRobotModel("urdf", config); });
    EXPECT_THAT(e.what(), HasSubstr("a urdf robot needs `tip_link`"));
  }
}

}  // namespace
}  // namespace cellmetry
