// Fields shared by job, simulation and comparison files (config_fields.h): a pose, a recording
// folder, a job file's kind, each an InputError at its node when wrong.
#include "cellmetry/formats/config_fields.h"

#include <cmath>
#include <filesystem>
#include <vector>

namespace cellmetry {

namespace {

// `key` of `node`, three numbers each within +-max_abs, refused at the entry that is not.
std::vector<double> ThreeWithin(const ConfigNode& node, const std::string& key, double max_abs,
                                const std::string& what, const std::string& hint) {
  const ConfigNode list = node[key];
  const auto v = list.AsDoubles(3);
  for (size_t i = 0; i < v.size(); ++i) {
    if (std::abs(v[i]) > max_abs) throw list.Elements()[i].Error(what, hint);
  }
  return v;
}

}  // namespace

// A pose in a config: a position beyond 100 m (a job's start 1e300 mm away made the fit's cost
// overflow: "the fit diverged", with no file to fix) or a rotation vector longer than any
// rotation needs is a typo or a unit mix-up.
Pose ReadPose(const ConfigNode& node) {
  Pose pose;
  if (node.Has("xyz")) {
    const auto v = ThreeWithin(node, "xyz", 1e5, "beyond any cell (|value| <= 1e5 mm)",
                               "Give the position in mm, within 100 m");
    pose.t = Eigen::Vector3d(v[0], v[1], v[2]);
  }
  if (node.Has("rvec")) {
    const auto v =
        ThreeWithin(node, "rvec", 10.0, "longer than any rotation vector (|value| <= 10 rad)",
                    "Give the rotation vector in rad: its length is the angle, at "
                    "most pi");
    const Eigen::Vector3d rvec(v[0], v[1], v[2]);
    pose.R = RotationFromRvec(rvec.data());
  }
  return pose;
}

std::string ReadRecordingPath(const ConfigNode& node) {
  const std::string folder = node.ResolvePath(node.AsString());
  std::error_code unreadable;  // a name the file system refuses (too long) is "no recording"
  if (!std::filesystem::is_regular_file(folder + "/recording.yaml", unreadable)) {
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
