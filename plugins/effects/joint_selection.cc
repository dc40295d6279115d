// The joints a per-joint effect acts on (joint_selection.h): the 1-based `joints:` list read and
// checked against the robot, and joint names in words.
#include "joint_selection.h"

namespace cellmetry::effects {

std::vector<int> SelectJoints(const ConfigNode& config, const RobotModel& robot) {
  std::vector<int> joints;
  if (!config.Has("joints")) {
    for (int i = 0; i < robot.num_joints(); ++i) joints.push_back(i);
    return joints;
  }
  for (const auto& node : config["joints"].Elements()) joints.push_back(SelectJoint(node, robot));
  if (joints.empty()) throw config["joints"].Error("lists no joint", "e.g. joints: [2, 3]");
  return joints;
}

int SelectJoint(const ConfigNode& node, const RobotModel& robot) {
  const int joint = node.AsInt();
  if (joint < 1 || joint > robot.num_joints()) {
    throw node.Error("no joint " + std::to_string(joint) + " on a " +
                         std::to_string(robot.num_joints()) + "-joint robot",
                     "Joints are numbered from 1");
  }
  return joint - 1;
}

std::string JointName(int joint) { return "j" + std::to_string(joint + 1); }

std::string JointsInWords(const std::vector<int>& joints) {
  std::string out = joints.size() == 1 ? "joint " : "joints ";
  for (size_t i = 0; i < joints.size(); ++i) {
    out += (i ? ", " : "") + std::to_string(joints[i] + 1);
  }
  return out;
}

}  // namespace cellmetry::effects
