// `cellmetry export`: every format read back by a reader of its own and held against cellmetry's
// own forward kinematics (the robot model plugin, built through the registry from the robot
// config, at the values result.json reports).
//
// The cell: configs/simulations/ur3_pair_geometry.yaml and configs/jobs/ur3_pair_geometry.yaml,
// two UR3s whose first one's joint offsets, two link lengths and a Hayati tilt are fitted (not
// nominal), run through the real command line once per suite; and the delta calibration
// (configs/jobs/delta_calibration.yaml) for what a non-serial arm can and cannot be exported as.
//
//   urdf   parsed by urdfdom (urdf::parseURDF); the tool's pose found by walking the parsed tree
//          from `world` (fixed origins, continuous joints about their axes) matches
//          T_world_base FK(q) T_flange_tool to 1e-9 m and 1e-9 rad over 500 random joint vectors
//   ur     the YAML's six xyz/rpy sections composed as ur_description does (then its fixed
//          wrist_3 -> flange -> tool0 joints) match FK(q) in the base frame, same tolerance
//   robot  the exported config, loaded by the plugin, gives the fitted FK (to 1e-9 mm)
//   tf     every node's transform equals its result.json frame; the robot-to-robot comment's
//          transform equals T_world_ur3^-1 T_world_ur3b
// and the pieces: roll-pitch-yaw round trips (gimbal lock included) and matches urdfdom's
// setFromRPY, the robot-to-robot sigma's Jacobian against central differences, bad input
// (exit 2, one line) and output safety (a user's file is never replaced without --overwrite,
// the replaced file is kept as .previous).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <sstream>
#include <tuple>

#include <unistd.h>

#include "cellmetry/exports/relative_pose.h"
#include "cellmetry/exports/roll_pitch_yaw.h"
#include "cellmetry/formats/config_node.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

constexpr double kTolerance = 1e-9;  // m (and rad)
constexpr int kJointVectors = 500;

Pose FromRvecMm(const nlohmann::json& frame) {
  const auto xyz = frame.at("xyz_mm").get<std::vector<double>>();
  const auto rvec = frame.at("rvec_rad").get<std::vector<double>>();
  return PoseFromRvecT({rvec[0], rvec[1], rvec[2]}, {xyz[0], xyz[1], xyz[2]});
}

Eigen::Matrix3d Rpy(double roll, double pitch, double yaw) {  // fixed axes, written out
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// Position (in the unit of the poses) and rotation difference.
struct Mismatch {
  double position = 0.0;
  double rotation = 0.0;
  void Add(const Pose& a, const Pose& b) {
    position = std::max(position, (a.t - b.t).norm());
    rotation = std::max(rotation, RotationError(a.R, b.R).norm());
  }
};

std::vector<std::vector<double>> RandomJointVectors(int joints, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(-2.0 * M_PI, 2.0 * M_PI);
  std::vector<std::vector<double>> out(kJointVectors, std::vector<double>(joints));
  for (auto& q : out) {
    for (double& v : q) v = angle(rng);
  }
  return out;
}

// The configs a job and simulation name, copied into `dir` with the same relative layout, so
// that their relative paths (../robots, ../../results) resolve there.
void MirrorConfigs(const std::string& dir, const std::vector<std::string>& files) {
  for (const auto& file : files) {
    fs::create_directories(fs::path(dir + "/" + file).parent_path());
    fs::copy_file(testing::Source(file), dir + "/" + file, fs::copy_options::overwrite_existing);
  }
}

// A robot's model as cellmetry computes it: the plugin, built from the source tree's robot
// config through the registry, at the values result.json reports for it.
struct ReferenceRobot {
  std::unique_ptr<RobotModel> model;
  std::vector<double> values;
  Pose T_world_base;

  Pose Flange(const std::vector<double>& q) const {
    Pose T;
    EXPECT_TRUE(model->Forward(q.data(), values.data(), &T));
    return T;
  }
};

ReferenceRobot Reference(const nlohmann::json& result, const std::string& robot,
                         const std::string& config) {
  ReferenceRobot r;
  r.model = testing::Plugins().CreateRobotModel(
      ConfigNode::LoadFile(testing::Source(config))["type"].AsString(),
      ConfigNode::LoadFile(testing::Source(config)));
  for (const auto& v : result.at("robots").at(robot).at("model_values")) {
    r.values.push_back(v.at("value").get<double>());
  }
  EXPECT_EQ(r.values.size(), r.model->parameters().size());
  r.T_world_base = FromRvecMm(result.at("frames").at(robot + ".base"));
  return r;
}

class Exports : public ::testing::Test {
 protected:
  // Each test runs in a process of its own under ctest, in parallel with -j: a folder per process.
  static void SetUpTestSuite() {
    dir_ = testing::TempDir("exports/" + std::to_string(::getpid()));
    MirrorConfigs(
        dir_, {"configs/robots/ur3_vsb2020.yaml", "configs/robots/delta.yaml",
               "configs/simulations/ur3_pair_geometry.yaml", "configs/jobs/ur3_pair_geometry.yaml",
               "configs/simulations/delta_uniform_125.yaml",
               "configs/simulations/delta_validation.yaml", "configs/jobs/delta_calibration.yaml"});
    for (const auto& [spec, out] : std::vector<std::pair<std::string, std::string>>{
             {"ur3_pair_geometry", "ur3_pair"},
             {"delta_uniform_125", "delta_sim"},
             {"delta_validation", "delta_validation"}}) {
      const auto sim = testing::RunCellmetry("simulate " + dir_ + "/configs/simulations/" + spec +
                                             ".yaml -o " + dir_ + "/results/" + out);
      ASSERT_EQ(sim.exit_code, 0) << sim.output;
    }
    for (const auto& job : {"ur3_pair_geometry", "delta_calibration"}) {
      const auto run = testing::RunCellmetry("run " + dir_ + "/configs/jobs/" + job + ".yaml");
      ASSERT_EQ(run.exit_code, 0) << run.output;
    }
    ur3_result_ = dir_ + "/results/ur3_pair_fit";
    delta_result_ = dir_ + "/results/delta_calibration";
  }

  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static nlohmann::json Json(const std::string& folder) {
    std::ifstream in(folder + "/result.json");
    return nlohmann::json::parse(in);
  }

  // `cellmetry export` into a fresh file; its text.
  static std::string Export(const std::string& result, const std::string& arguments,
                            const std::string& name) {
    const std::string path = dir_ + "/exports/" + name;
    fs::create_directories(dir_ + "/exports");
    fs::remove(path);
    fs::remove(path + ".previous");
    const auto r = testing::RunCellmetry("export " + result + " " + arguments + " -o " + path);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return testing::ReadText(path);
  }

  static std::string dir_, ur3_result_, delta_result_;
};

std::string Exports::dir_, Exports::ur3_result_, Exports::delta_result_;

// The fit moved the model: what the exports carry is not the nominal table.
TEST_F(Exports, TheResultsModelIsFittedAndRecordedWhole) {
  const nlohmann::json result = Json(ur3_result_);
  const ReferenceRobot ur3 = Reference(result, "ur3", "configs/robots/ur3_vsb2020.yaml");
  double largest_change = 0.0;
  for (size_t i = 0; i < ur3.values.size(); ++i) {
    largest_change =
        std::max(largest_change, std::abs(ur3.values[i] - ur3.model->parameters()[i].nominal));
  }
  EXPECT_GT(largest_change, 0.1);  // mm: j3.a and j4.a moved by ~0.3 mm
  // The record agrees with the fitted parameters result.json has always reported.
  int fitted = 0;
  for (const auto& p : result.at("model_parameters")) {
    const std::string name = p.at("name").get<std::string>();
    if (name.rfind("ur3.model.", 0) != 0) continue;
    const int index = FindParameter(ur3.model->parameters(), name.substr(10));
    ASSERT_GE(index, 0) << name;
    EXPECT_EQ(ur3.values[index], p.at("value").get<double>()) << name;
    ++fitted;
  }
  EXPECT_EQ(fitted, 6);
}

// The URDF, as urdfdom parses it, walked from `world` to the tool.
TEST_F(Exports, UrdfParsedByUrdfdomMatchesTheFittedForwardKinematics) {
  const std::string urdf = Export(ur3_result_, "--format urdf --robot ur3", "ur3.urdf");
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf);
  ASSERT_TRUE(model) << urdf;
  ASSERT_EQ(model->getRoot()->name, "world");
  const nlohmann::json result = Json(ur3_result_);
  const ReferenceRobot ur3 = Reference(result, "ur3", "configs/robots/ur3_vsb2020.yaml");
  const Pose T_flange_tool = FromRvecMm(result.at("frames").at("tool"));

  // The joints from the tool link up to the root, then composed root first.
  std::vector<urdf::JointConstSharedPtr> chain;
  for (urdf::LinkConstSharedPtr link = model->getLink("tool"); link && link->parent_joint;
       link = link->getParent()) {
    chain.insert(chain.begin(), link->parent_joint);
  }
  ASSERT_EQ(chain.size(), 9u);  // world->base, six joints, link6->flange, flange->tool
  std::vector<double> nominal;
  for (const auto& p : ur3.model->parameters()) nominal.push_back(p.nominal);
  Mismatch mismatch, off_nominal;
  for (const auto& q : RandomJointVectors(6, 7)) {
    Pose T_world_tool_m = Pose::Identity();
    int movable = 0;
    for (const auto& joint : chain) {
      const urdf::Pose& o = joint->parent_to_joint_origin_transform;
      Pose origin;
      origin.t = {o.position.x, o.position.y, o.position.z};
      origin.R = Eigen::Quaterniond(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z)
                     .toRotationMatrix();
      T_world_tool_m = T_world_tool_m * origin;
      if (joint->type == urdf::Joint::FIXED) continue;
      ASSERT_TRUE(joint->type == urdf::Joint::CONTINUOUS || joint->type == urdf::Joint::REVOLUTE);
      ASSERT_EQ(joint->name, "ur3_joint" + std::to_string(movable + 1));
      const Eigen::Vector3d axis(joint->axis.x, joint->axis.y, joint->axis.z);
      Pose turn;
      turn.R = Eigen::AngleAxisd(q[movable++], axis).toRotationMatrix();
      T_world_tool_m = T_world_tool_m * turn;
    }
    ASSERT_EQ(movable, 6);
    Pose cellmetry_m = ur3.T_world_base * ur3.Flange(q) * T_flange_tool;
    cellmetry_m.t /= 1000.0;
    mismatch.Add(T_world_tool_m, cellmetry_m);
    // The comparison can tell: the nominal table misses by the fit's correction.
    Pose nominal_flange;
    ASSERT_TRUE(ur3.model->Forward(q.data(), nominal.data(), &nominal_flange));
    Pose nominal_m = ur3.T_world_base * nominal_flange * T_flange_tool;
    nominal_m.t /= 1000.0;
    off_nominal.Add(T_world_tool_m, nominal_m);
  }
  EXPECT_GT(off_nominal.position, 1e-4);  // m
  std::printf("URDF vs cellmetry FK (tool in world, %d joint vectors): %.3g m, %.3g rad\n",
              kJointVectors, mismatch.position, mismatch.rotation);
  EXPECT_LE(mismatch.position, kTolerance);
  EXPECT_LE(mismatch.rotation, kTolerance);
  // What a URDF cannot hold is said in the file.
  EXPECT_THAT(urdf, HasSubstr("cellmetry-export: urdf"));
  EXPECT_THAT(urdf, HasSubstr("ur3.model.j3.beta = "));
  EXPECT_THAT(urdf, HasSubstr("Not in this file"));
}

// Universal Robots' kinematics YAML, composed as ur_description composes it.
TEST_F(Exports, UrKinematicsYamlMatchesTheFittedForwardKinematics) {
  const std::string text = Export(ur3_result_, "--format ur --robot ur3", "ur3_kinematics.yaml");
  const YAML::Node kinematics = YAML::Load(text)["kinematics"];
  ASSERT_TRUE(kinematics.IsMap()) << text;
  EXPECT_TRUE(std::regex_match(kinematics["hash"].as<std::string>(),
                               std::regex("calib_cellmetry_[0-9a-f]{16}")));
  const std::vector<std::string> sections = {"shoulder", "upper_arm", "forearm",
                                             "wrist_1",  "wrist_2",   "wrist_3"};
  std::vector<Pose> origins;
  for (const auto& name : sections) {
    const YAML::Node s = kinematics[name];
    ASSERT_TRUE(s.IsMap()) << name;
    Pose origin;
    origin.t = {s["x"].as<double>(), s["y"].as<double>(), s["z"].as<double>()};
    origin.R = Rpy(s["roll"].as<double>(), s["pitch"].as<double>(), s["yaw"].as<double>());
    origins.push_back(origin);
  }
  // ur_description: wrist_3_link -> flange (rpy 0 -pi/2 -pi/2) -> tool0 (rpy pi/2 0 pi/2).
  Pose wrist3_tool0;
  wrist3_tool0.R = Rpy(0, -M_PI / 2, -M_PI / 2) * Rpy(M_PI / 2, 0, M_PI / 2);
  const nlohmann::json result = Json(ur3_result_);
  const ReferenceRobot ur3 = Reference(result, "ur3", "configs/robots/ur3_vsb2020.yaml");
  Mismatch mismatch;
  for (const auto& q : RandomJointVectors(6, 8)) {
    Pose T_base_tool0 = Pose::Identity();
    for (int i = 0; i < 6; ++i) {
      Pose turn;
      turn.R = Eigen::AngleAxisd(q[i], Eigen::Vector3d::UnitZ()).toRotationMatrix();
      T_base_tool0 = T_base_tool0 * origins[i] * turn;
    }
    T_base_tool0 = T_base_tool0 * wrist3_tool0;
    Pose cellmetry_m = ur3.Flange(q);
    cellmetry_m.t /= 1000.0;
    mismatch.Add(T_base_tool0, cellmetry_m);
  }
  std::printf("UR kinematics vs cellmetry FK (tool0 in base, %d joint vectors): %.3g m, %.3g rad\n",
              kJointVectors, mismatch.position, mismatch.rotation);
  EXPECT_LE(mismatch.position, kTolerance);
  EXPECT_LE(mismatch.rotation, kTolerance);
  EXPECT_THAT(text, HasSubstr("base_joint (parent -> base_link)"));
}

// The calibrated robot config, loaded by its plugin, is the fitted robot.
TEST_F(Exports, RobotConfigLoadsAsTheFittedModel) {
  for (const auto& [result_folder, robot, config] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {ur3_result_, "ur3", "configs/robots/ur3_vsb2020.yaml"},
           {delta_result_, "delta", "configs/robots/delta.yaml"}}) {
    const std::string path = dir_ + "/exports/" + robot + "_calibrated.yaml";
    Export(result_folder, "--format robot --robot " + robot, robot + "_calibrated.yaml");
    const ConfigNode exported = ConfigNode::LoadFile(path);
    const auto model = testing::Plugins().CreateRobotModel(exported["type"].AsString(), exported);
    std::vector<double> nominal;
    for (const auto& p : model->parameters()) nominal.push_back(p.nominal);
    const ReferenceRobot fitted = Reference(Json(result_folder), robot, config);
    ASSERT_EQ(nominal.size(), fitted.values.size());
    Mismatch mismatch;
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> angle(robot == "delta" ? -0.2 : -2 * M_PI,
                                                 robot == "delta" ? 0.6 : 2 * M_PI);
    int compared = 0;
    for (int trial = 0; trial < kJointVectors; ++trial) {
      std::vector<double> q(model->num_joints());
      for (double& v : q) v = angle(rng);
      Pose a, b;
      const bool ok_a = model->Forward(q.data(), nominal.data(), &a);
      const bool ok_b = fitted.model->Forward(q.data(), fitted.values.data(), &b);
      ASSERT_EQ(ok_a, ok_b);
      if (!ok_a) continue;
      mismatch.Add(a, b);
      ++compared;
    }
    EXPECT_GT(compared, kJointVectors / 2) << robot;
    std::printf("robot config vs fitted FK (%s, %d joint vectors): %.3g mm, %.3g rad\n",
                robot.c_str(), compared, mismatch.position, mismatch.rotation);
    EXPECT_LE(mismatch.position, kTolerance * 1000.0) << robot;  // mm
    EXPECT_LE(mismatch.rotation, kTolerance) << robot;
    // The delta keeps what its config held beside the arms.
    if (robot == "delta") {
      EXPECT_EQ(model->limits().joint_min_rad.size(), 3u);
      EXPECT_NEAR(model->nominal_tool().t.z(), -60.0, 1e-12);
    }
  }
}

// Every frame of result.json comes back from the launch file's nodes.
TEST_F(Exports, TfLaunchFileHoldsEveryFrameOfTheResult) {
  const std::string launch = Export(ur3_result_, "--format tf", "cell.launch.xml");
  std::map<std::string, std::pair<std::string, Pose>> nodes;  // child -> parent, T (m)
  const std::regex args("args=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(launch.begin(), launch.end(), args);
       it != std::sregex_iterator(); ++it) {
    std::istringstream tokens((*it)[1].str());
    std::map<std::string, std::string> a;
    for (std::string key, value; tokens >> key >> value;) a[key] = value;
    Pose T;
    T.t = {std::stod(a.at("--x")), std::stod(a.at("--y")), std::stod(a.at("--z"))};
    T.R = Eigen::Quaterniond(std::stod(a.at("--qw")), std::stod(a.at("--qx")),
                             std::stod(a.at("--qy")), std::stod(a.at("--qz")))
              .toRotationMatrix();
    nodes[a.at("--child-frame-id")] = {a.at("--frame-id"), T};
  }
  const nlohmann::json frames = Json(ur3_result_).at("frames");
  ASSERT_EQ(nodes.size(), frames.size());  // 2 bases, 2 tools, 2 cameras
  EXPECT_EQ(nodes.size(), 6u);
  auto ros = [](std::string name) {
    std::replace(name.begin(), name.end(), '.', '_');
    return name;
  };
  for (const auto& [name, frame] : frames.items()) {
    ASSERT_TRUE(nodes.count(ros(name))) << name;
    const auto& [parent, T_m] = nodes.at(ros(name));
    EXPECT_EQ(parent, ros(frame.at("parent").get<std::string>())) << name;
    Pose expected = FromRvecMm(frame);
    expected.t /= 1000.0;
    Mismatch mismatch;
    mismatch.Add(T_m, expected);
    EXPECT_LE(mismatch.position, 1e-12) << name;
    EXPECT_LE(mismatch.rotation, 1e-12) << name;
    // Its sigma, in the comment before it.
    EXPECT_THAT(launch,
                HasSubstr(name + " in " + frame.at("parent").get<std::string>() + ": sigma xyz ("));
  }
  // Robot to robot: ur3b's base in ur3's, in a comment.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      launch, m,
      std::regex("ur3b_base in ur3_base: xyz \\(m\\) = \\(([^,]+), ([^,]+), ([^)]+)\\)")));
  const Pose relative =
      FromRvecMm(frames.at("ur3.base")).inverse() * FromRvecMm(frames.at("ur3b.base"));
  EXPECT_NEAR(std::stod(m[1]), relative.t.x() / 1000.0, 1e-12);
  EXPECT_NEAR(std::stod(m[2]), relative.t.y() / 1000.0, 1e-12);
  EXPECT_NEAR(std::stod(m[3]), relative.t.z() / 1000.0, 1e-12);
}

// `--names ur`: ur_description's names; tool0 is the fitted flange (the tool on it, in the world,
// matches FK as above); tf hangs the base as base_link and the tool from tool0.
TEST_F(Exports, UrNamesPutTool0AtTheFittedFlangeInUrdfAndTf) {
  const std::string urdf = Export(ur3_result_, "--format urdf --robot ur3 --names ur", "ur3.ur");
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf);
  ASSERT_TRUE(model) << urdf;
  for (const char* joint : {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                            "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"}) {
    EXPECT_TRUE(model->getJoint(joint)) << joint;
  }
  ASSERT_EQ(model->getLink("tool")->getParent()->name, "tool0");
  const nlohmann::json result = Json(ur3_result_);
  const ReferenceRobot ur3 = Reference(result, "ur3", "configs/robots/ur3_vsb2020.yaml");
  const Pose T_flange_tool = FromRvecMm(result.at("frames").at("tool"));
  const char* names[6] = {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                          "wrist_1_joint",      "wrist_2_joint",       "wrist_3_joint"};
  Mismatch mismatch;
  for (const auto& q : RandomJointVectors(6, 9)) {
    Pose T_world_tool_m = Pose::Identity();
    for (urdf::LinkConstSharedPtr link = model->getLink("tool"); link->parent_joint;
         link = link->getParent()) {
      const urdf::JointConstSharedPtr joint = link->parent_joint;
      const urdf::Pose& o = joint->parent_to_joint_origin_transform;
      Pose origin;
      origin.t = {o.position.x, o.position.y, o.position.z};
      origin.R = Eigen::Quaterniond(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z)
                     .toRotationMatrix();
      Pose turn;
      for (int i = 0; i < 6; ++i) {
        if (joint->name == names[i])
          turn.R = Eigen::AngleAxisd(q[i], Eigen::Vector3d::UnitZ()).toRotationMatrix();
      }
      T_world_tool_m = origin * turn * T_world_tool_m;
    }
    Pose cellmetry_m = ur3.T_world_base * ur3.Flange(q) * T_flange_tool;
    cellmetry_m.t /= 1000.0;
    mismatch.Add(T_world_tool_m, cellmetry_m);
  }
  std::printf("URDF (--names ur) vs cellmetry FK: %.3g m, %.3g rad\n", mismatch.position,
              mismatch.rotation);
  EXPECT_LE(mismatch.position, kTolerance);
  EXPECT_LE(mismatch.rotation, kTolerance);

  const std::string tf = Export(ur3_result_, "--format tf --robot ur3 --names ur", "ur3_tf.launch");
  EXPECT_THAT(tf, HasSubstr("--frame-id world --child-frame-id base_link\""));
  EXPECT_THAT(tf, HasSubstr("--frame-id tool0 --child-frame-id tool\""));
  EXPECT_THAT(tf, HasSubstr("--child-frame-id ur3b_base\""));  // the other robot keeps its names
  const auto ur = testing::RunCellmetry("export " + ur3_result_ + " --format ur --names ur");
  testing::ExpectOneLineError(ur, "--names:", "--names ur applies to --format urdf and tf");
  const auto bad = testing::RunCellmetry("export " + ur3_result_ + " --format urdf --names ros");
  testing::ExpectOneLineError(bad, "--names:", "unknown naming 'ros'");
}

TEST_F(Exports, ADeltaArmIsRefusedAsUrdfAndUrNamingWhatIsPossible) {
  for (const auto& format : {"urdf", "ur"}) {
    const auto r = testing::RunCellmetry("export " + delta_result_ + " --format " + format);
    testing::ExpectOneLineError(
        r, delta_result_ + "/result.json:", "is not a serial chain of revolute joints");
    EXPECT_THAT(r.output, HasSubstr("--format robot"));
    EXPECT_THAT(r.output, HasSubstr("--format tf"));
  }
  const auto tf = testing::RunCellmetry("export " + delta_result_ + " --format tf");
  EXPECT_EQ(tf.exit_code, 0) << tf.output;
  EXPECT_THAT(tf.output, HasSubstr("--child-frame-id stereo"));
  const auto ur = testing::RunCellmetry("export " + delta_result_ + " --format urdf --names ur");
  testing::ExpectOneLineError(
      ur, delta_result_ + "/result.json:", "--names ur names a six-joint serial arm");
}

TEST_F(Exports, BadInputIsOneLineAndExitCodeTwo) {
  const std::string bad = testing::TempDirForThisTest("exports_bad");
  testing::ExpectOneLineError(testing::RunCellmetry("export " + bad + "/none --format urdf"),
                              bad + "/none:", "no such result folder");
  testing::ExpectOneLineError(testing::RunCellmetry("export " + bad + " --format urdf"),
                              bad + "/result.json:", "cannot open the result");
  testing::ExpectOneLineError(
      testing::RunCellmetry("export " + ur3_result_ + " --format sdf"),
      "--format:", "unknown export format 'sdf'. Give one of: urdf, ur, tf, robot");
  testing::ExpectOneLineError(
      testing::RunCellmetry("export " + ur3_result_ + " --format urdf"),
      ur3_result_ + "/result.json:", "several robots (ur3, ur3b). Name one with --robot");
  testing::ExpectOneLineError(
      testing::RunCellmetry("export " + ur3_result_ + " --format urdf --robot ur9"),
      ur3_result_ + "/result.json:", "has no robot 'ur9'. Its robots: ur3, ur3b");
  // A result written before results recorded their robots' models, and one with no robot.
  nlohmann::json result = Json(ur3_result_);
  result.erase("robots");
  testing::WriteText(bad + "/old/result.json", result.dump());
  testing::ExpectOneLineError(testing::RunCellmetry("export " + bad + "/old --format urdf"),
                              bad + "/old/result.json:", "does not record its robots' models");
  result["robots"] = nlohmann::json::object();
  testing::WriteText(bad + "/robotless/result.json", result.dump());
  testing::ExpectOneLineError(testing::RunCellmetry("export " + bad + "/robotless --format robot"),
                              bad + "/robotless/result.json:", "the result has no robot to export");
  testing::WriteText(bad + "/garbage/result.json", "{\"format\": \"something else\"}");
  testing::ExpectOneLineError(testing::RunCellmetry("export " + bad + "/garbage --format tf"),
                              bad + "/garbage/result.json:", "not a cellmetry result");
}

// A result edited by hand is refused at the key that is wrong, by `export` and `evaluate` alike:
// both read result.json through one reader (formats/workcell_result_file.h).
TEST_F(Exports, AMalformedResultIsRefusedAtItsKey) {
  const std::string bad = testing::TempDirForThisTest("exports_malformed");
  nlohmann::json result = Json(ur3_result_);
  result["frames"]["ur3.base"]["xyz_mm"][1] = "two";
  testing::WriteText(bad + "/text/result.json", result.dump());
  for (const std::string& command : {"export " + bad + "/text --format tf",
                                     "evaluate " + bad + "/text " + bad + "/truth.yaml"}) {
    testing::ExpectOneLineError(testing::RunCellmetry(command), bad + "/text/result.json:",
                                "malformed result: frames.ur3.base.xyz_mm[1]: expected a number");
  }
  result = Json(ur3_result_);
  result.erase("free_parameters");
  testing::WriteText(bad + "/short/result.json", result.dump());
  testing::ExpectOneLineError(
      testing::RunCellmetry("export " + bad + "/short --format tf"),
      bad + "/short/result.json:", "malformed result: no 'free_parameters'");
  // A covariance that does not fit the free parameters would give every sigma an export or a
  // compensated command reports as zero or wrong.
  result = Json(ur3_result_);
  const size_t n = result["free_parameters"].size();
  result["sigma"].erase(result["sigma"].size() - 1);
  testing::WriteText(bad + "/sigma/result.json", result.dump());
  testing::ExpectOneLineError(testing::RunCellmetry("export " + bad +
                                                    "/sigma --format robot "
                                                    "--robot ur3"),
                              bad + "/sigma/result.json:",
                              "malformed result: sigma has " + std::to_string(n - 1) +
                                  " entries for " + std::to_string(n) + " free parameters");
  result = Json(ur3_result_);
  result["correlation"][2].erase(0);
  testing::WriteText(bad + "/row/result.json", result.dump());
  testing::ExpectOneLineError(
      testing::RunCellmetry("export " + bad + "/row --format robot --robot ur3"),
      bad + "/row/result.json:",
      "malformed result: correlation[2] has " + std::to_string(n - 1) + " entries");
  // The calibration's joint ranges, which compensate checks commands against: a range upside
  // down, and one range too few for the model's joints.
  result = Json(ur3_result_);
  ASSERT_TRUE(result["robots"]["ur3"].contains("joint_ranges_rad"));
  result["robots"]["ur3"]["joint_ranges_rad"][1] = {0.5, -0.5};
  testing::WriteText(bad + "/range/result.json", result.dump());
  testing::ExpectOneLineError(
      testing::RunCellmetry("export " + bad + "/range --format robot --robot ur3"),
      bad + "/range/result.json:",
      "malformed result: robots.ur3.joint_ranges_rad[1]: expected [min, max] with min <= max");
  result = Json(ur3_result_);
  result["robots"]["ur3"]["joint_ranges_rad"].erase(5);
  testing::WriteText(bad + "/ranges/result.json", result.dump());
  testing::ExpectOneLineError(
      testing::RunCellmetry("export " + bad + "/ranges --format robot --robot ur3"),
      bad + "/ranges/result.json:", "robot 'ur3' records 5 joint ranges, its model has 6 joints");
}

TEST_F(Exports, NeverReplacesAFileCellmetryDidNotWrite) {
  const std::string out = testing::TempDirForThisTest("exports_safety");
  const std::string file = out + "/robot.urdf";
  const std::string export_urdf = "export " + ur3_result_ + " --format urdf --robot ur3 -o ";
  testing::WriteText(file, "<robot name=\"mine\"/>\n");
  const auto refused = testing::RunCellmetry(export_urdf + file);
  testing::ExpectOneLineError(refused, file + ":", "was not written by `cellmetry export`");
  EXPECT_EQ(testing::ReadText(file), "<robot name=\"mine\"/>\n");
  EXPECT_FALSE(fs::exists(file + ".previous"));
  // --overwrite replaces it, and keeps it.
  ASSERT_EQ(testing::RunCellmetry(export_urdf + file + " --overwrite").exit_code, 0);
  EXPECT_THAT(testing::ReadText(file), HasSubstr("cellmetry-export: urdf"));
  EXPECT_EQ(testing::ReadText(file + ".previous"), "<robot name=\"mine\"/>\n");
  // The user's file now in the .previous slot is not replaced by the next export either.
  const auto slot = testing::RunCellmetry(export_urdf + file);
  testing::ExpectOneLineError(slot, file + ".previous:", "not one cellmetry wrote");
  EXPECT_EQ(testing::ReadText(file + ".previous"), "<robot name=\"mine\"/>\n");
  // An earlier export is replaced and kept one generation deep.
  fs::remove(file + ".previous");
  const auto again = testing::RunCellmetry("export " + ur3_result_ + " --format tf -o " + file);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_THAT(testing::ReadText(file), HasSubstr("cellmetry-export: tf"));
  EXPECT_THAT(testing::ReadText(file + ".previous"), HasSubstr("cellmetry-export: urdf"));
  // A folder is no file.
  testing::ExpectOneLineError(testing::RunCellmetry(export_urdf + out), out + ":",
                              "the export path is not a file");
  // Nothing half-written is left behind.
  for (const auto& entry : fs::directory_iterator(out)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  }
}

// R = Rz(yaw) Ry(pitch) Rx(roll) back and forth, gimbal lock included; and it is urdfdom's.
TEST(RollPitchYaw, RoundTripsExactlyEverywhereAndIsUrdfdomsConvention) {
  std::vector<Eigen::Matrix3d> rotations;
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.5);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d rvec(normal(rng), normal(rng), normal(rng));
    rotations.push_back(RotationFromRvec(rvec.data()));
  }
  for (const double pitch :
       {M_PI / 2, -M_PI / 2, M_PI / 2 - 1e-7, -M_PI / 2 + 1e-9, M_PI / 2 - 1e-12}) {
    for (const double other : {0.0, 0.3, -2.9, 3.14159}) {
      rotations.push_back(Rpy(other, pitch, 0.7 - other));
      rotations.push_back(Rpy(0.2, pitch, other));
    }
  }
  double worst = 0.0;
  for (const auto& R : rotations) {
    const RollPitchYawAngles a = RollPitchYaw(R);
    EXPECT_LE(std::abs(a.pitch), M_PI / 2);
    worst = std::max(worst, (RotationFromRollPitchYaw(a) - R).norm());
    urdf::Rotation u;
    u.setFromRPY(a.roll, a.pitch, a.yaw);
    const Eigen::Matrix3d from_urdfdom = Eigen::Quaterniond(u.w, u.x, u.y, u.z).toRotationMatrix();
    EXPECT_LE((from_urdfdom - R).norm(), 1e-14);
  }
  EXPECT_LE(worst, 1e-14);
}

// The robot-to-robot sigma's Jacobian against central differences of the exact relative pose.
TEST(RelativePose, JacobianMatchesCentralDifferences) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto random_pose = [&] {
    const Eigen::Vector3d rvec(normal(rng), normal(rng), normal(rng));
    return PoseFromRvecT(rvec, Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * 500.0);
  };
  auto perturbed = [](const Pose& T, const Eigen::Matrix<double, 6, 1>& d) {
    const Eigen::Vector3d phi = d.tail<3>();
    return Pose{RotationFromRvec(phi.data()) * T.R, T.t + d.head<3>()};
  };
  for (int trial = 0; trial < 20; ++trial) {
    const Pose a = random_pose(), b = random_pose();
    const Pose T_ab = a.inverse() * b;
    const Eigen::Matrix<double, 6, 12> J = RelativePoseJacobian(a, b);
    for (int k = 0; k < 12; ++k) {
      const double h = k % 6 < 3 ? 1e-3 : 1e-6;
      Eigen::Matrix<double, 6, 1> da = Eigen::Matrix<double, 6, 1>::Zero(), db = da;
      (k < 6 ? da : db)[k % 6] = h;
      const Pose plus = perturbed(a, da).inverse() * perturbed(b, db);
      const Pose minus = perturbed(a, -da).inverse() * perturbed(b, -db);
      Eigen::Matrix<double, 6, 1> numeric;
      numeric.head<3>() = (plus.t - minus.t) / (2 * h);
      numeric.tail<3>() =
          (RotationError(plus.R, T_ab.R) - RotationError(minus.R, T_ab.R)) / (2 * h);
      EXPECT_LE((numeric - J.col(k)).norm(), 1e-6 * std::max(1.0, J.col(k).norm()))
          << "column " << k << ": numeric " << numeric.transpose() << ", analytic "
          << J.col(k).transpose();
    }
  }
}

}  // namespace
}  // namespace cellmetry
