// ReadUrdfChain (urdf_chain.h): urdfdom parses the file; the chain is walked from the tip up to
// the base through each link's parent joint, since a URDF is a tree and a link has one parent.
#include "urdf_chain.h"

#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <set>

#include "cellmetry/basics/text.h"
#include "cellmetry/basics/utf8.h"
#include "cellmetry/formats/input_file.h"

namespace cellmetry::urdf_robot {

namespace {

constexpr double kMmPerMetre = 1000.0;

Pose PoseOf(const urdf::Pose& origin) {
  Pose pose;
  const urdf::Rotation& r = origin.rotation;
  pose.R = Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix();
  pose.t = Eigen::Vector3d(origin.position.x, origin.position.y, origin.position.z) * kMmPerMetre;
  return pose;
}

// A URDF is text of some KB (meshes are files of their own); 64 MB bounds what a link to a
// device or a wrong file can make the reader take.
constexpr std::uintmax_t kMaxUrdfBytes = std::uintmax_t{64} << 20;

// The URDF's text, read as input_file.h reads any file a user names. Its refusal is raised
// again at the robot config's `file:`, where the user wrote the path.
std::string ReadFile(const ConfigNode& config, const std::string& path) {
  try {
    return ReadRegularFile(path, kMaxUrdfBytes, "Give its path relative to this robot config");
  } catch (const InputError& e) {
    throw config["file"].Error("cannot read the URDF '" + path + "': " + e.message(), e.hint());
  }
}

// Line and column (1-based) of a byte of `text`.
SourceLocation At(const std::string& text, size_t byte, const std::string& path) {
  const size_t line_start = text.rfind('\n', byte) + 1;  // 0 on the first line (npos + 1)
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + byte, '\n'));
  return {path, line, 1 + static_cast<int>(byte - line_start)};
}

// urdfdom hands some of its parse errors, with the value that failed in them, to its logger as
// the printf format (`CONSOLE_BRIDGE_logError(e.what())`): a '%' in a malformed number then
// reads arguments that are not there and can crash the process. Comments never reach it.
void RequireNoPercentOutsideComments(const std::string& text, const std::string& path) {
  for (size_t i = 0; i < text.size(); ++i) {
    if (text.compare(i, 4, "<!--") == 0) {
      const size_t end = text.find("-->", i + 4);
      if (end == std::string::npos) return;  // urdfdom refuses the unclosed comment itself
      i = end + 2;
      continue;
    }
    if (text[i] != '%') continue;
    throw InputError(At(text, i, path),
                     "a '%' outside a comment: urdfdom can pass a value that fails to parse to "
                     "its log as a format, where a '%' crashes it",
                     "Write the value without '%' (a number needs none; a mesh path's %20 is a "
                     "space)");
  }
}

// Text urdfdom's XML parser can take: UTF-8 without a NUL. TinyXML steps over a multi-byte
// character by its first byte's count, so a character cut short at the end of the file sends it
// reading past the text (utf8.h); it stops at a NUL, so what follows one would go unread.
void RequireXmlText(const std::string& text, const std::string& path) {
  std::optional<size_t> bad = FirstInvalidUtf8Byte(text);
  const size_t nul = text.find('\0');
  if (nul != std::string::npos && (!bad || nul < *bad)) bad = nul;
  if (!bad) return;
  char byte[8];
  std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>(text[*bad]));
  throw InputError(At(text, *bad, path),
                   std::string("the byte ") + byte +
                       (text[*bad] == '\0' ? " (NUL) has no place in a URDF"
                                           : " is not UTF-8, the encoding a URDF is read in"),
                   "Save the URDF as UTF-8 text (xacro writes it so); a file in another 8-bit "
                   "encoding shows such a byte at its first accented letter");
}

std::vector<std::string> LinkNames(const urdf::ModelInterface& model) {
  std::vector<urdf::LinkSharedPtr> links;
  model.getLinks(links);
  std::vector<std::string> names;
  for (const auto& link : links) names.push_back(link->name);
  std::sort(names.begin(), names.end());
  return names;
}

// The named link, or an InputError at `key` that names the file, the nearest name and the links.
urdf::LinkConstSharedPtr FindLink(const urdf::ModelInterface& model, const ConfigNode& config,
                                  const std::string& key, const std::string& file) {
  const std::string name = config[key].AsString();
  urdf::LinkConstSharedPtr link = model.getLink(name);
  if (link) return link;
  const std::vector<std::string> names = LinkNames(model);
  const std::string nearest = NearestWord(name, names);
  throw config[key].Error("no link '" + name + "' in " + file,
                          (nearest.empty() ? std::string() : "Did you mean '" + nearest + "'? ") +
                              "Its links: " + Join(names));
}

std::string TypeName(int type) {
  switch (type) {
    case urdf::Joint::PRISMATIC: return "prismatic";
    case urdf::Joint::PLANAR: return "planar";
    case urdf::Joint::FLOATING: return "floating";
    default: return "of unknown type";
  }
}

// The joint as the URDF has it, for exports under its names; `movable` is set by the caller.
UrdfPathJoint PathJoint(const urdf::Joint& joint, const Pose& origin) {
  UrdfPathJoint out;
  out.name = joint.name;
  out.parent_link = joint.parent_link_name;
  out.child_link = joint.child_link_name;
  out.origin = origin;
  if (joint.type == urdf::Joint::REVOLUTE && joint.limits) {
    out.limit = NamedJointLimit{joint.limits->lower, joint.limits->upper, joint.limits->effort,
                                joint.limits->velocity};
  }
  return out;
}

// The joints from `base` down to `tip`, in that order: the walk goes up from the tip, each
// link's parent joint; the root has none. urdfdom accepts a joint whose parent is its own child
// (or a longer loop), so a link met twice ends the walk.
std::vector<urdf::JointConstSharedPtr> JointsFromBaseToTip(const urdf::ModelInterface& model,
                                                           const urdf::LinkConstSharedPtr& base,
                                                           const urdf::LinkConstSharedPtr& tip,
                                                           const ConfigNode& config,
                                                           const std::string& file) {
  std::vector<urdf::JointConstSharedPtr> path;
  std::string walked = tip->name;
  std::set<std::string> visited = {tip->name};
  for (urdf::LinkConstSharedPtr link = tip; link != base;) {
    const urdf::JointConstSharedPtr joint = link->parent_joint;
    if (!joint) {
      throw config["tip_link"].Error(
          "link '" + tip->name + "' is not below '" + base->name + "' in " + file +
              " (from it up to the root: " + walked + ")",
          "Name as base_link a link on that path, and as tip_link one below it");
    }
    path.push_back(joint);
    link = model.getLink(joint->parent_link_name);
    if (!link) {  // urdfdom refuses such a file; kept so that a null is never walked
      throw config["file"].Error("joint '" + joint->name + "' in " + file +
                                 " hangs from a link the file does not have");
    }
    if (!visited.insert(link->name).second) {
      throw config["file"].Error("the joints of " + file + " form a loop: joint '" + joint->name +
                                     "' has '" + joint->parent_link_name +
                                     "' as parent, met before on the way up from '" + tip->name +
                                     "' (" + walked + ")",
                                 "Give each joint the parent link it hangs from");
    }
    walked += " <- " + link->name;
  }
  std::reverse(path.begin(), path.end());
  return path;
}

// A joint that moves, as the model reads it: revolute or continuous, its own reading (no mimic),
// a direction for its axis.
UrdfJoint MovableJoint(const urdf::Joint& joint, const Pose& origin, const Pose& T_previous_parent,
                       const UrdfChain& chain, const ConfigNode& config) {
  const std::string& file = chain.file;
  if (joint.type != urdf::Joint::REVOLUTE && joint.type != urdf::Joint::CONTINUOUS) {
    throw config["tip_link"].Error(
        "joint '" + joint.name + "' on the chain from '" + chain.base_link + "' to '" +
            chain.tip_link + "' in " + file + " is " + TypeName(joint.type) +
            ": the urdf robot model has revolute and continuous joints only",
        "End the chain before it (tip_link: '" + joint.parent_link_name + "')");
  }
  if (joint.mimic) {
    throw config["tip_link"].Error(
        "joint '" + joint.name + "' in " + file + " mimics '" + joint.mimic->joint_name +
            "': the urdf robot model reads one controller reading per joint",
        "End the chain before it (tip_link: '" + joint.parent_link_name + "')");
  }
  const Eigen::Vector3d axis(joint.axis.x, joint.axis.y, joint.axis.z);
  if (!(axis.norm() > 1e-9)) {
    throw config["file"].Error("joint '" + joint.name + "' in " + file + " has a zero <axis>",
                               "Give the joint's axis as a direction, e.g. <axis xyz=\"0 0 1\"/>");
  }
  UrdfJoint movable;
  movable.name = joint.name;
  movable.T_previous_parent = T_previous_parent;
  movable.xyz_mm = origin.t;
  movable.R_parent_joint = origin.R;
  movable.axis = axis.normalized();
  return movable;
}

}  // namespace

UrdfChain ReadUrdfChain(const ConfigNode& config) {
  UrdfChain chain;
  chain.file = config.ResolvePath(config["file"].AsString());
  const std::string text = ReadFile(config, chain.file);
  RequireXmlText(text, chain.file);
  RequireNoPercentOutsideComments(text, chain.file);
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
  if (!model) {
    throw config["file"].Error(
        "urdfdom cannot parse '" + chain.file + "' (its reason is printed above)",
        "Check the XML; expand a xacro file first: xacro robot.urdf.xacro > robot.urdf");
  }
  const urdf::LinkConstSharedPtr base = FindLink(*model, config, "base_link", chain.file);
  const urdf::LinkConstSharedPtr tip = FindLink(*model, config, "tip_link", chain.file);
  chain.base_link = base->name;
  chain.tip_link = tip->name;

  Pose folded = Pose::Identity();  // fixed joints since the last movable one
  for (const urdf::JointConstSharedPtr& joint :
       JointsFromBaseToTip(*model, base, tip, config, chain.file)) {
    const Pose origin = PoseOf(joint->parent_to_joint_origin_transform);
    chain.path.push_back(PathJoint(*joint, origin));
    if (joint->type == urdf::Joint::FIXED) {
      folded = folded * origin;
      continue;
    }
    chain.path.back().movable = static_cast<int>(chain.joints.size());
    chain.joints.push_back(MovableJoint(*joint, origin, folded, chain, config));
    folded = Pose::Identity();
  }
  chain.T_last_joint_tip = folded;
  if (chain.joints.empty()) {
    throw config["tip_link"].Error("no revolute or continuous joint between '" + base->name +
                                       "' and '" + tip->name + "' in " + chain.file,
                                   "Name the links at the two ends of the arm");
  }
  return chain;
}

}  // namespace cellmetry::urdf_robot
