// Fields shared by job, simulation and comparison files (config_fields.h): a pose, a recording
// folder, a job file's kind, each an InputError at its node when wrong.
#include "cellmetry/formats/config_fields.h"

#include <filesystem>

namespace cellmetry {

Pose ReadPose(const ConfigNode& node) {
  Pose pose;
  if (node.Has("xyz")) {
    const auto v = node["xyz"].AsDoubles(3);
    pose.t = Eigen::Vector3d(v[0], v[1], v[2]);
  }
  if (node.Has("rvec")) {
    const auto v = node["rvec"].AsDoubles(3);
    const Eigen::Vector3d rvec(v[0], v[1], v[2]);
    pose.R = RotationFromRvec(rvec.data());
  }
  return pose;
}

std::string ReadRecordingPath(const ConfigNode& node) {
  const std::string folder = node.ResolvePath(node.AsString());
  if (!std::filesystem::is_regular_file(folder + "/recording.yaml")) {
    throw node.Error("no recording at '" + folder + "' (expected " + folder + "/recording.yaml)",
                     "Point '" + node.key_path() +
                         ":' at a cellmetry-recording/1 folder, relative to the job file");
  }
  return folder;
}

std::string JobKind(const std::string& path) {
  return ConfigNode::LoadFile(path)["job"].AsString();
}

}  // namespace cellmetry
