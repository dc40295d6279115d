// The effect library's default candidates (default_candidates.h), in the order the finder lists
// them: per robot its joints, the couplings the job names, rod pairs and thermal growth; then per
// camera and per target what they get wrong; then the world tag's frame; then, when asked, the
// causes shared by every camera or target.
#include "default_candidates.h"

#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace cellmetry::effects {
namespace {

OfferedCandidate Offer(const std::string& config, const std::string& name, const std::string& robot,
                       const std::string& label, const std::string& hint) {
  OfferedCandidate c;
  c.name = name;
  c.robot = robot;
  c.config = config;
  c.label = label;
  c.data_hint = hint;
  return c;
}

std::string JoinedNumbers(const std::vector<double>& values) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : ", ") + std::to_string(v);
  return out;
}

// A parallel arm's links (a delta's three rod pairs) at its nominal geometry's zero joint
// readings; 0 for a serial arm.
int ParallelLinkCount(const RobotModel& model) {
  std::vector<double> q(model.num_joints(), 0.0), nominal;
  for (const auto& p : model.parameters()) nominal.push_back(p.nominal);
  std::vector<ParallelLink> links;
  return model.ParallelLinks(q.data(), nominal.data(), &links) ? static_cast<int>(links.size()) : 0;
}

// Per joint: its compliance (under `masses`, the job's link masses, "" for the model's own),
// backlash (held by the last move, and by gravity), transmission error (each harmonic alone, and
// `harmonics` together) and gear ratio error.
void AddJointCandidates(const CandidateCell::Robot& robot, const std::string& masses,
                        const std::string& harmonics, std::vector<OfferedCandidate>* out) {
  const std::string prefix = robot.name + ".";
  const std::string with_masses = masses.empty() ? "" : ", link_masses_kg: [" + masses + "]";
  for (int j = 1; j <= robot.model->num_joints(); ++j) {
    const std::string J = std::to_string(j), joint = "joint " + J;
    out->push_back(Offer("{type: joint_compliance, joints: [" + J + "]" + with_masses + "}",
                         prefix + "compliance_j" + J, robot.name, joint + " compliance",
                         "poses that load " + joint + " differently (outstretched and folded)"));
    // A spring that stiffens and play that gravity holds against a flank both give with the
    // gravity torque, less than linearly at large loads: one cause, "the joint gives under
    // gravity", whose curve's shape tells the mechanism (one group, as a camera's calibration).
    const std::string gravity_group = prefix + "gravity_load_j" + J;
    const std::string gravity_label = joint + " giving under gravity";
    out->back().group = gravity_group;
    out->back().group_label = gravity_label;
    // Backlash where the last move holds the joint, and where gravity does: one family.
    const std::string backlash = prefix + "backlash_j" + J;
    out->push_back(Offer("{type: backlash, joints: [" + J + "]}", backlash, robot.name,
                         joint + " backlash", "moves into poses from both directions on " + joint));
    out->back().family = backlash;
    out->push_back(
        Offer("{type: backlash, joints: [" + J + "], held_by: gravity" + with_masses + "}",
              backlash + "_gravity", robot.name, joint + " backlash held by gravity",
              "poses that load " + joint +
                  " by different amounts the same way "
                  "(payloads)"));
    out->back().family = backlash;
    out->back().group = gravity_group;
    out->back().group_label = gravity_label;
    // One candidate per harmonic (two parameters each, so that a single harmonic does not pay
    // for four) and one with them all (where the error has several, each alone carries only
    // its share); one family, since all name the same physics.
    const std::string family = prefix + "transmission_j" + J;
    for (const std::string& h : std::vector<std::string>{"1", "2", harmonics}) {
      const bool all = h == harmonics;
      out->push_back(
          Offer("{type: transmission_error, joints: [" + J + "], harmonics: [" + h + "]}",
                all ? family : family + "_h" + h, robot.name,
                joint + " transmission error" + (all ? "" : " (harmonic " + h + ")"),
                "a wider range of " + joint + " (at least half a turn)"));
      out->back().family = family;
    }
    out->push_back(Offer("{type: joint_scale, joints: [" + J + "]}", prefix + "scale_j" + J,
                         robot.name, joint + " gear ratio error", "a wider range of " + joint));
  }
}

// Per coupling the job names (a wrist whose driven joint's shaft runs through the driving one),
// on each robot that has both joints.
void AddCouplingCandidates(const CandidateCell::Robot& robot,
                           const std::vector<std::array<int, 2>>& couplings,
                           std::vector<OfferedCandidate>* out) {
  for (const auto& [driving, driven] : couplings) {
    if (std::max(driving, driven) > robot.model->num_joints()) continue;
    const std::string from = std::to_string(driving), to = std::to_string(driven);
    out->push_back(Offer("{type: joint_coupling, joints: [" + to + "], from: " + from + "}",
                         robot.name + ".coupling_j" + to + "_j" + from, robot.name,
                         "joint " + to + " coupled to joint " + from,
                         "a wider range of joint " + from + " with joint " + to +
                             " seen turning (a rotation or an off-axis target)"));
  }
}

// Per rod pair of a parallel arm (none for a serial one): its parallelogram's skew and its ball
// joints' clearance.
void AddParallelLinkCandidates(const CandidateCell::Robot& robot,
                               std::vector<OfferedCandidate>* out) {
  const int links = ParallelLinkCount(*robot.model);
  for (int i = 1; i <= links; ++i) {
    const std::string I = std::to_string(i), arm = "arm " + I;
    out->push_back(Offer("{type: platform_tilt, arms: [" + I + "]}", robot.name + ".tilt_arm" + I,
                         robot.name, arm + " parallelogram skew",
                         "poses that turn " + arm + "'s rods further"));
    out->push_back(Offer("{type: ball_joint_clearance, arms: [" + I + "]}",
                         robot.name + ".clearance_arm" + I, robot.name,
                         arm + " ball-joint clearance",
                         "poses near the workspace edge, where " + arm +
                             "'s load share changes "
                             "most"));
  }
}

// Thermal growth as the recorded temperature drives it, and as a warm-up from a cold start in
// time: a temperature read at the controller or in the room need not follow the arm's own
// warming (on the suite's UR3, a warm-up over time against a temperature ramped linearly was
// named 1 time in 5 with the temperature form alone). One family: both name the arm's thermal
// growth, and the bootstrap counts either as it.
void AddThermalCandidates(const CandidateCell::Robot& robot, const CandidateCell& cell,
                          std::vector<OfferedCandidate>* out) {
  const std::string thermal = robot.name + ".thermal";
  if (cell.temperatures || !cell.times) {
    out->push_back(Offer("{type: thermal_drift}", thermal, robot.name, "thermal growth of the arm",
                         "temperatures over a range of several degrees"));
  }
  if (cell.times) {
    out->push_back(Offer(
        "{type: thermal_drift, model: warmup}", cell.temperatures ? thermal + "_warmup" : thermal,
        robot.name, "thermal growth while warming up", "captures from a cold start over an hour"));
    out->back().family = thermal;
  }
}

// A camera's calibration in one of the forms a pose estimator passes on, which every camera of a
// cell may have at once (the same calibration procedure, the same mistake).
struct CameraForm {
  std::string name;           // the candidate's name before "_<camera>" ("camera.principal")
  std::string atom;           // OfferedCandidate::atoms, before "/<camera>"
  std::string label;          // after the camera's name, or "every camera's " + label
  std::string yaml;           // the effect's block less its cameras
  std::string before, after;  // the data that makes it testable: before + camera + after
  std::string config(const std::string& on) const { return "{" + yaml + ", " + on + "}"; }
  std::string hint(const std::string& camera) const { return before + camera + after; }
};

const std::vector<CameraForm> kCameraForms = {
    {"camera.depth_tilt", "depth_tilt", "depth error tilting across the image",
     "type: depth_bias, terms: [tilt]", "targets spread across ", "'s image"},
    {"camera.focal", "focal", "focal length", "type: camera_intrinsics, terms: [focal]",
     "targets at more varied distances from ", ""},
    {"camera.principal", "principal", "principal point",
     "type: camera_intrinsics, terms: [principal]", "targets turned more and spread across ",
     "'s image"},
};

// Per camera its depth (along the ray, and tilting across the image), its focal length,
// principal point, radial distortion (k1) and whole lens distortion (k1, k2, p1, p2) as a pose
// estimator passes them on, one group: the six are first-order pieces of one calibration, and
// over the part of the image the targets cross a real lens's error looks like one or another of
// them (docs/physics.md).
void AddCameraCandidates(const std::string& camera, const std::string& any,
                         std::vector<OfferedCandidate>* out) {
  const std::string on = "cameras: [" + camera + "]";
  const size_t first = out->size();
  out->push_back(Offer("{type: depth_bias, " + on + "}", "camera.depth_" + camera, any,
                       camera + " depth bias", "targets at more varied distances from " + camera));
  out->back().atoms = {"depth/" + camera};
  for (const CameraForm& form : kCameraForms) {
    out->push_back(Offer(form.config(on), form.name + "_" + camera, any, camera + " " + form.label,
                         form.hint(camera)));
    out->back().atoms = {form.atom + "/" + camera};
  }
  // The lens: k1 alone, and k1 with k2 and the tangential p1, p2 (a real lens's error has all
  // four), one family since the first is nested in the second (once one is accepted, the other
  // would repeat its k1).
  const std::string lens = "camera.lens_" + camera;
  out->push_back(Offer("{type: camera_intrinsics, " + on + ", terms: [radial]}",
                       "camera.radial_" + camera, any, camera + " radial distortion",
                       "targets near the edges of " + camera + "'s image"));
  out->back().family = lens;
  out->back().atoms = {"radial/" + camera};
  out->push_back(Offer("{type: camera_intrinsics, " + on + ", terms: [radial, k2, tangential]}",
                       lens, any, camera + " lens distortion",
                       "targets near the edges of " + camera + "'s image"));
  out->back().family = lens;
  out->back().atoms = {"radial/" + camera, "lens/" + camera};
  for (size_t k = first; k < out->size(); ++k) {
    (*out)[k].group = "camera.calibration_" + camera;
    (*out)[k].group_label = camera + " calibration";
  }
}

// Per target its printed size and (where its measured rotation is fitted: the world tag's
// always) the pose estimator's tilt of it; the world tag's tilt from the frame the placement was
// measured in (a frame where the job states a robot level, untestable otherwise: a gauge, which
// the absorption test finds).
void AddTargetCandidates(const CandidateCell& cell, const std::string& any,
                         std::vector<OfferedCandidate>* out) {
  for (const std::string& target : cell.targets) {
    out->push_back(Offer("{type: target_scale, targets: [" + target + "]}",
                         "target.scale_" + target, any, target + " printed size",
                         "targets at more varied distances"));
    out->back().atoms = {"scale/" + target};
    if (target != cell.world_target && !cell.use_tool_rotation) continue;
    out->push_back(Offer("{type: target_tilt, targets: [" + target + "]}", "target.tilt_" + target,
                         any, target + " pose estimates tilted",
                         "the target seen from more directions"));
  }
  const bool world_seen =
      !cell.world_target.empty() &&
      std::find(cell.targets.begin(), cell.targets.end(), cell.world_target) != cell.targets.end();
  if (!world_seen) return;
  out->push_back(Offer("{type: world_frame, target: " + cell.world_target + "}", "world_frame", any,
                       "world tag tilted from the placement's frame",
                       "a robot standing level stated in the job (base: {level: {sigma_rad}}), "
                       "or its base's rotation measured and held"));
  out->back().frame = cell.level_stated;
}

// With two or more cameras, each camera form on every camera at once (one candidate whose atoms
// are each camera's, so that a cause shared by the cameras is tested as one); with two or more
// targets, every target's printed size at once, and all of them printed on one printer.
void AddSharedCauseCandidates(const CandidateCell& cell, const std::string& any,
                              std::vector<OfferedCandidate>* out) {
  if (cell.cameras.size() >= 2) {
    std::string list;
    for (const auto& camera : cell.cameras) list += (list.empty() ? "" : ", ") + camera;
    for (const CameraForm& form : kCameraForms) {
      out->push_back(Offer(form.config("cameras: [" + list + "]"), form.name + "_every_camera", any,
                           "every camera's " + form.label, form.hint("every camera")));
      for (const auto& camera : cell.cameras) out->back().atoms.push_back(form.atom + "/" + camera);
      // Like one camera's forms, pieces of one calibration procedure's error: one group.
      out->back().group = "camera.calibration_every_camera";
      out->back().group_label = "every camera's calibration";
    }
  }
  if (cell.targets.size() < 2) return;
  std::string list;
  std::vector<std::string> atoms;
  for (const std::string& target : cell.targets) {
    list += (list.empty() ? "" : ", ") + target;
    atoms.push_back("scale/" + target);
  }
  out->push_back(Offer("{type: target_scale, targets: [" + list + "]}", "target.scale_every_target",
                       any, "every target's printed size", "targets at more varied distances"));
  out->back().atoms = atoms;
  out->push_back(Offer("{type: target_scale, targets: [" + list + "], shared: true}",
                       "target.scale_one_printer", any, "every target printed at one wrong size",
                       "targets at more varied distances"));
  out->back().atoms = atoms;
}

}  // namespace

std::vector<OfferedCandidate> OfferCandidates(const CandidateCell& cell) {
  std::vector<OfferedCandidate> out;
  if (cell.robots.empty()) return out;
  std::string harmonics = "1, 2";
  for (int h : cell.gear_harmonics) {
    if (h > 2) harmonics += ", " + std::to_string(h);
  }
  const std::string masses = JoinedNumbers(cell.link_masses_kg);
  for (const CandidateCell::Robot& robot : cell.robots) {
    AddJointCandidates(robot, masses, harmonics, &out);
    AddCouplingCandidates(robot, cell.joint_couplings, &out);
    AddParallelLinkCandidates(robot, &out);
    AddThermalCandidates(robot, cell, &out);
  }
  const std::string& any = cell.robots.front().name;  // measurement effects act on every chain
  for (const std::string& camera : cell.cameras) AddCameraCandidates(camera, any, &out);
  AddTargetCandidates(cell, any, &out);
  if (cell.group_candidates) AddSharedCauseCandidates(cell, any, &out);
  return out;
}

}  // namespace cellmetry::effects
