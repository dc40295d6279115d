// `cellmetry export --names ur`: a six-joint arm under ur_description's names and frames, read
// back by urdfdom.
//
//   frames   for UR5e's config (configs/robots/ur5e.yaml, UR's DH) at its nominal values, every
//            link of the exported URDF (base, shoulder_link ... wrist_3_link, flange, tool0) sits
//            in base_link where a chain written out by hand from ur_description does (its
//            ur_macro.xacro joints with UR5e's default_kinematics.yaml origins, pi/2 exact where
//            the YAML rounds it), at a few joint vectors, to 1e-9 m and rad
//   tool0    for a perturbed ("calibrated") table, tool0 in the world is T_world_base FK(q) and
//            the tool T_world_base FK(q) T_flange_tool, over random joint vectors
//   refusal  a delta arm and a seven-joint chain: InputError naming --names ur
// The cell is built in memory (CalibratedCell) around the plugin's model, so that no fit runs.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <map>
#include <random>

#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/exports/urdf_export.h"
#include "cellmetry/formats/config_node.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

constexpr double kTolerance = 1e-9;  // m, rad

Pose Rpy(double roll, double pitch, double yaw, const Eigen::Vector3d& xyz_m = {0, 0, 0}) {
  Pose T;
  T.R = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
  T.t = xyz_m;
  return T;
}

Pose TurnZ(double angle) { return Rpy(0, 0, angle); }

// A result of one robot from `config` (a file in the source tree) at `values`, its base and a
// tool placed somewhere.
CalibratedCell OneRobotCell(const std::string& config_file, const std::string& name,
                            const std::function<void(std::vector<double>*)>& perturb = {}) {
  CalibratedCell cell;
  cell.folder = "in-memory";
  cell.json_path = "in-memory/result.json";
  CalibratedRobot robot;
  robot.name = name;
  const ConfigNode config = ConfigNode::LoadFile(testing::Source(config_file));
  robot.model_type = config["type"].AsString();
  robot.model_config = std::make_shared<ConfigNode>(config);
  robot.model = testing::Plugins().CreateRobotModel(robot.model_type, config);
  for (const Parameter& p : robot.model->parameters()) robot.values.push_back(p.nominal);
  if (perturb) perturb(&robot.values);
  cell.robots.push_back(robot);
  cell.frames.push_back({name + ".base", "world", Rpy(0.1, -0.2, 0.7, {812.0, -95.0, 40.0}), {}});
  cell.frames.push_back({"tool", name + ".flange", Rpy(0.0, 0.3, 0.0, {5.0, 0.0, 120.0}), {}});
  return cell;
}

// `link`'s pose in `from` (metres) at joint values by name, walked up through the parsed tree.
Pose LinkPose(const urdf::ModelInterface& model, const std::string& from, const std::string& link,
              const std::map<std::string, double>& q) {
  Pose T = Pose::Identity();
  for (urdf::LinkConstSharedPtr l = model.getLink(link); l && l->name != from; l = l->getParent()) {
    const urdf::JointConstSharedPtr joint = l->parent_joint;
    EXPECT_TRUE(joint) << link << " is not below " << from;
    if (!joint) break;
    const urdf::Pose& o = joint->parent_to_joint_origin_transform;
    Pose origin;
    origin.t = {o.position.x, o.position.y, o.position.z};
    origin.R = Eigen::Quaterniond(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z)
                   .toRotationMatrix();
    Pose turn;
    if (joint->type != urdf::Joint::FIXED) {
      const Eigen::Vector3d axis(joint->axis.x, joint->axis.y, joint->axis.z);
      turn.R = Eigen::AngleAxisd(q.at(joint->name), axis).toRotationMatrix();
    }
    T = origin * turn * T;
  }
  return T;
}

const std::vector<std::string> kUrJoints = {"shoulder_pan_joint", "shoulder_lift_joint",
                                            "elbow_joint",        "wrist_1_joint",
                                            "wrist_2_joint",      "wrist_3_joint"};

std::map<std::string, double> ByName(const std::vector<double>& q) {
  std::map<std::string, double> out;
  for (size_t i = 0; i < kUrJoints.size(); ++i) out[kUrJoints[i]] = q[i];
  return out;
}

// ur_description's UR5e, written out by hand: each link in base_link at q.
std::map<std::string, Pose> UrDescriptionUr5e(const std::vector<double>& q) {
  const double h = M_PI / 2;
  const std::vector<std::pair<std::string, Pose>> arm = {
      {"shoulder_link", Rpy(0, 0, 0, {0, 0, 0.1625})},
      {"upper_arm_link", Rpy(h, 0, 0)},
      {"forearm_link", Rpy(0, 0, 0, {-0.425, 0, 0})},
      {"wrist_1_link", Rpy(0, 0, 0, {-0.3922, 0, 0.1333})},
      {"wrist_2_link", Rpy(h, 0, 0, {0, -0.0997, 0})},
      {"wrist_3_link", Rpy(h, M_PI, M_PI, {0, 0.0996, 0})}};
  std::map<std::string, Pose> links;
  links["base_link_inertia"] = TurnZ(M_PI);
  links["base"] = TurnZ(M_PI);
  Pose T = links["base_link_inertia"];
  for (size_t i = 0; i < arm.size(); ++i) {
    T = T * arm[i].second * TurnZ(q[i]);
    links[arm[i].first] = T;
  }
  links["flange"] = T * Rpy(0, -h, -h);
  links["tool0"] = links["flange"] * Rpy(h, 0, h);
  return links;
}

double PositionError(const Pose& a, const Pose& b) { return (a.t - b.t).norm(); }
double AngleError(const Pose& a, const Pose& b) { return RotationError(a.R, b.R).norm(); }

TEST(RosNames, Ur5eLinksSitWhereUrDescriptionPutsThem) {
  const CalibratedCell cell = OneRobotCell("configs/robots/ur5e.yaml", "ur5e");
  const std::string text = UrdfExport(cell, cell.robots[0], ExportNaming::kUr);
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
  ASSERT_TRUE(model) << text;
  for (const auto& joint : kUrJoints) EXPECT_TRUE(model->getJoint(joint)) << joint;
  for (const char* fixed : {"base_joint", "base_link-base_link_inertia",
                            "base_link-base_fixed_joint", "wrist_3-flange", "flange-tool0"}) {
    ASSERT_TRUE(model->getJoint(fixed)) << fixed;
    EXPECT_EQ(model->getJoint(fixed)->type, urdf::Joint::FIXED) << fixed;
  }
  EXPECT_EQ(model->getLink("tool")->getParent()->name, "tool0");
  double worst_m = 0.0, worst_rad = 0.0;
  int compared = 0;
  for (const std::vector<double>& q : std::vector<std::vector<double>>{
           {0, 0, 0, 0, 0, 0},
           {0.3, -1.2, 1.9, -0.4, 1.1, 2.5},
           {-2.8, 0.7, -2.2, 3.0, -1.6, -0.9},
           {1.5707963267948966, -1.5707963267948966, 0, -1.5707963267948966, 0, 0}}) {
    for (const auto& [link, expected] : UrDescriptionUr5e(q)) {
      const Pose got = LinkPose(*model, "base_link", link, ByName(q));
      worst_m = std::max(worst_m, PositionError(got, expected));
      worst_rad = std::max(worst_rad, AngleError(got, expected));
      ++compared;
    }
  }
  EXPECT_EQ(compared, 4 * 10);
  std::printf("UR5e links vs ur_description, %d frames: %.3g m, %.3g rad\n", compared, worst_m,
              worst_rad);
  EXPECT_LE(worst_m, kTolerance);
  EXPECT_LE(worst_rad, kTolerance);
}

TEST(RosNames, Tool0IsTheCalibratedFlangeInTheWorld) {
  const CalibratedCell cell = OneRobotCell("configs/robots/ur5e.yaml", "ur5e", [](auto* v) {
    for (size_t k = 0; k < v->size(); ++k) (*v)[k] += 1e-3 * static_cast<double>(k % 7 + 1);
  });
  const CalibratedRobot& robot = cell.robots[0];
  const urdf::ModelInterfaceSharedPtr model =
      urdf::parseURDF(UrdfExport(cell, robot, ExportNaming::kUr));
  ASSERT_TRUE(model);
  const Pose T_world_base = cell.frames[0].T_parent_frame;
  const Pose T_flange_tool = cell.frames[1].T_parent_frame;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-2 * M_PI, 2 * M_PI);
  double worst_m = 0.0, worst_rad = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> q(6);
    for (double& v : q) v = angle(rng);
    Pose flange;
    ASSERT_TRUE(robot.model->Forward(q.data(), robot.values.data(), &flange));
    for (const auto& [link, T_mm] : std::vector<std::pair<std::string, Pose>>{
             {"tool0", T_world_base * flange}, {"tool", T_world_base * flange * T_flange_tool}}) {
      Pose expected = T_mm;
      expected.t /= 1000.0;
      const Pose got = LinkPose(*model, "world", link, ByName(q));
      worst_m = std::max(worst_m, PositionError(got, expected));
      worst_rad = std::max(worst_rad, AngleError(got, expected));
    }
  }
  std::printf("tool0 and tool vs calibrated FK: %.3g m, %.3g rad\n", worst_m, worst_rad);
  EXPECT_LE(worst_m, kTolerance);
  EXPECT_LE(worst_rad, kTolerance);
}

TEST(RosNames, ArmsThatAreNotSixJointSerialAreRefused) {
  {
    const CalibratedCell cell = OneRobotCell("configs/robots/delta.yaml", "delta");
    const InputError e =
        testing::CatchInputError([&] { UrdfExport(cell, cell.robots[0], ExportNaming::kUr); });
    EXPECT_THAT(e.what(), HasSubstr("--names ur names a six-joint serial arm"));
    EXPECT_THAT(e.what(), HasSubstr("not a serial chain"));
    EXPECT_THAT(e.what(), HasSubstr("Leave out --names ur"));
  }
  {
    const std::string dir = testing::TempDirForThisTest("ros_names");
    std::string seven = "type: serial_mdh\nname: seven\nunits: {length: mm, angle: rad}\njoints:\n";
    for (int i = 0; i < 7; ++i) {
      seven += "  - {alpha: " + std::string(i % 2 ? "1.5707963267948966" : "0") +
               ", a: 0, d: 100, offset: 0}\n";
    }
    testing::WriteText(dir + "/seven.yaml", seven);
    CalibratedCell cell = OneRobotCell("configs/robots/ur5e.yaml", "arm");
    CalibratedRobot& robot = cell.robots[0];
    robot.model = testing::Plugins().CreateRobotModel("serial_mdh",
                                                      ConfigNode::LoadFile(dir + "/seven.yaml"));
    robot.values.clear();
    for (const Parameter& p : robot.model->parameters()) robot.values.push_back(p.nominal);
    const InputError e =
        testing::CatchInputError([&] { UrdfExport(cell, robot, ExportNaming::kUr); });
    EXPECT_THAT(e.what(), HasSubstr("a chain of 7 joints"));
    // Under the model's names the same arm exports.
    EXPECT_TRUE(urdf::parseURDF(UrdfExport(cell, robot, ExportNaming::kModel)));
  }
}

}  // namespace
}  // namespace cellmetry
