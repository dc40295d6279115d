// The physics finder's default candidates (diagnosis.h): the effect library, each effect on one
// joint or camera at a time, so that a finding names the joint or camera.
#include <algorithm>
#include <string>
#include <vector>

#include "cellmetry/diagnosis/diagnosis.h"

namespace cellmetry {
namespace {

CandidateEffect Make(const std::string& yaml, const std::string& name, const WorkcellRobot& robot,
                     const std::string& label, const std::string& hint, Registry& registry) {
  const ConfigNode config = ConfigNode::LoadString(yaml, "default candidates");
  CandidateEffect c;
  c.type = config["type"].AsString();
  c.effect.name = name;
  c.effect.robot = robot.name;
  c.effect.effect = registry.CreateEffect(c.type, config, *robot.model);
  c.effect.config = config.FlowText();
  c.label = label;
  c.data_hint = hint;
  c.site = CandidateSite(config, robot.name);
  return c;
}

// A parallel arm's links (a delta's three rod pairs) at its nominal geometry's zero joint
// readings; 0 for a serial arm.
int ParallelLinkCount(const RobotModel& model) {
  std::vector<double> q(model.num_joints(), 0.0), nominal;
  for (const auto& p : model.parameters()) nominal.push_back(p.nominal);
  std::vector<ParallelLink> links;
  return model.ParallelLinks(q.data(), nominal.data(), &links) ? static_cast<int>(links.size()) : 0;
}

// A camera's calibration in one of the forms a pose estimator passes on, which every camera of a
// cell may have at once (the same calibration procedure, the same mistake).
struct CameraForm {
  std::string name;   // the candidate's name before "_<camera>" ("camera.principal")
  std::string atom;   // CandidateEffect::atoms, before "/<camera>"
  std::string label;  // after the camera's name, or "every camera's " + label
  std::string yaml;   // the effect's block less its cameras
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

// With two or more cameras, each form of kCameraForms on every camera at once: one candidate
// whose atoms are each camera's, so that a cause shared by the cameras is tested as one.
void AddEveryCameraCandidates(const Recording& recording, const WorkcellRobot& any,
                              Registry& registry, std::vector<CandidateEffect>* out) {
  if (recording.cameras.size() < 2) return;
  std::string list;
  for (const auto& camera : recording.cameras) list += (list.empty() ? "" : ", ") + camera;
  for (const CameraForm& form : kCameraForms) {
    out->push_back(Make(form.config("cameras: [" + list + "]"), form.name + "_every_camera", any,
                        "every camera's " + form.label, form.hint("every camera"), registry));
    for (const auto& camera : recording.cameras) out->back().atoms.push_back(form.atom + "/" + camera);
    // Like one camera's forms, pieces of one calibration procedure's error: one group.
    out->back().group = "camera.calibration_every_camera";
    out->back().group_label = "every camera's calibration";
  }
}

// With two or more targets, every target's printed size at once, and all of them printed on one
// printer (one shared scale): a cause shared by the boards tested as one.
void AddEveryTargetCandidates(const Recording& recording, const WorkcellRobot& any,
                              Registry& registry, std::vector<CandidateEffect>* out) {
  if (recording.targets.size() < 2) return;
  std::string list;
  std::vector<std::string> atoms;
  for (const auto& [target, carrier] : recording.targets) {
    list += (list.empty() ? "" : ", ") + target;
    atoms.push_back("scale/" + target);
  }
  out->push_back(Make("{type: target_scale, targets: [" + list + "]}", "target.scale_every_target",
                      any, "every target's printed size", "targets at more varied distances",
                      registry));
  out->back().atoms = atoms;
  out->push_back(Make("{type: target_scale, targets: [" + list + "], shared: true}",
                      "target.scale_one_printer", any, "every target printed at one wrong size",
                      "targets at more varied distances", registry));
  out->back().atoms = atoms;
}

// What a camera and the targets it measures get wrong: per camera its depth (along the ray, and
// tilting across the image), its focal length, principal point, radial distortion (k1) and
// whole lens distortion (k1, k2, p1, p2) as a pose estimator passes them on, one group
// (CandidateEffect::group); per target its printed size and the estimator's tilt of it; the
// world tag's tilt from the frame the placement was measured in (testable only where the bases'
// rotations are held: a gauge otherwise, which the absorption test finds).
void AddCameraCandidates(const WorkcellProblem& spec, const Recording& recording, bool groups,
                         Registry& registry, std::vector<CandidateEffect>* out) {
  const WorkcellRobot& any = spec.robots.front();
  for (const auto& camera : recording.cameras) {
    const std::string on = "cameras: [" + camera + "]";
    const size_t first = out->size();
    out->push_back(Make("{type: depth_bias, " + on + "}", "camera.depth_" + camera, any,
                        camera + " depth bias", "targets at more varied distances from " + camera,
                        registry));
    out->back().atoms = {"depth/" + camera};
    for (const CameraForm& form : kCameraForms) {
      out->push_back(Make(form.config(on), form.name + "_" + camera, any,
                          camera + " " + form.label, form.hint(camera), registry));
      out->back().atoms = {form.atom + "/" + camera};
    }
    // The lens: k1 alone, and k1 with k2 and the tangential p1, p2 (a real lens's error has all
    // four), one family since the first is nested in the second (once one is accepted, the other
    // would repeat its k1).
    const std::string lens = "camera.lens_" + camera;
    out->push_back(Make("{type: camera_intrinsics, " + on + ", terms: [radial]}",
                        "camera.radial_" + camera, any, camera + " radial distortion",
                        "targets near the edges of " + camera + "'s image", registry));
    out->back().family = lens;
    out->back().atoms = {"radial/" + camera};
    out->push_back(Make("{type: camera_intrinsics, " + on + ", terms: [radial, k2, tangential]}",
                        lens, any, camera + " lens distortion",
                        "targets near the edges of " + camera + "'s image", registry));
    out->back().family = lens;
    out->back().atoms = {"radial/" + camera, "lens/" + camera};
    // The six are first-order pieces of one calibration: over the part of the image the
    // targets cross, a real lens's error looks like one or another of them (docs/physics.md).
    for (size_t k = first; k < out->size(); ++k) {
      (*out)[k].group = "camera.calibration_" + camera;
      (*out)[k].group_label = camera + " calibration";
    }
  }
  for (const auto& [target, carrier] : recording.targets) {
    out->push_back(Make("{type: target_scale, targets: [" + target + "]}",
                        "target.scale_" + target, any, target + " printed size",
                        "targets at more varied distances", registry));
    out->back().atoms = {"scale/" + target};
    // The tilt acts on measured rotations: the world tag's always, a carried target's if used.
    if (target != spec.world_target && !spec.use_tool_rotation) continue;
    out->push_back(Make("{type: target_tilt, targets: [" + target + "]}",
                        "target.tilt_" + target, any, target + " pose estimates tilted",
                        "the target seen from more directions", registry));
  }
  if (!spec.world_target.empty() && recording.targets.count(spec.world_target)) {
    out->push_back(Make("{type: world_frame, target: " + spec.world_target + "}", "world_frame",
                        any, "world tag tilted from the placement's frame",
                        "a robot standing level stated in the job (base: {level: {sigma_rad}}), "
                        "or its base's rotation measured and held", registry));
    // Where the job states a robot level, the tag's tilt from level is a frame the statement
    // determines (CandidateEffect::frame); without it, nothing does and it is untestable.
    out->back().frame = std::any_of(spec.robots.begin(), spec.robots.end(),
                                    [](const WorkcellRobot& r) { return r.level_sigma_rad.has_value(); });
  }
  if (!groups) return;
  AddEveryCameraCandidates(recording, any, registry, out);
  AddEveryTargetCandidates(recording, any, registry, out);
}

// Per joint of `robot`: its compliance (under `masses`, the job's link masses, "" for the
// model's own), backlash (held by the last move, and by gravity), transmission error (each
// harmonic alone, and `harmonics` together) and gear ratio error.
void AddJointCandidates(const WorkcellRobot& robot, const std::string& masses,
                        const std::string& harmonics, Registry& registry,
                        std::vector<CandidateEffect>* out) {
  const std::string prefix = robot.name + ".";
  for (int j = 1; j <= robot.model->num_joints(); ++j) {
    const std::string J = std::to_string(j), joint = "joint " + J;
    out->push_back(Make("{type: joint_compliance, joints: [" + J + "]" +
                            (masses.empty() ? "" : ", link_masses_kg: [" + masses + "]") + "}",
                        prefix + "compliance_j" + J, robot, joint + " compliance",
                        "poses that load " + joint + " differently (outstretched and folded)",
                        registry));
    // A spring that stiffens and play that gravity holds against a flank both give with the
    // gravity torque, less than linearly at large loads: one cause, "the joint gives under
    // gravity", whose curve's shape tells the mechanism (one group, as a camera's calibration).
    const std::string gravity_group = prefix + "gravity_load_j" + J;
    const std::string gravity_label = joint + " giving under gravity";
    out->back().group = gravity_group;
    out->back().group_label = gravity_label;
    // Backlash where the last move holds the joint, and where gravity does: one family.
    const std::string backlash = prefix + "backlash_j" + J;
    out->push_back(Make("{type: backlash, joints: [" + J + "]}", backlash, robot,
                        joint + " backlash", "moves into poses from both directions on " + joint,
                        registry));
    out->back().family = backlash;
    out->push_back(Make("{type: backlash, joints: [" + J + "], held_by: gravity" +
                            (masses.empty() ? "" : ", link_masses_kg: [" + masses + "]") + "}",
                        backlash + "_gravity", robot, joint + " backlash held by gravity",
                        "poses that load " + joint + " by different amounts the same way "
                        "(payloads)", registry));
    out->back().family = backlash;
    out->back().group = gravity_group;
    out->back().group_label = gravity_label;
    // One candidate per harmonic (two parameters each, so that a single harmonic does not pay
    // for four) and one with them all (where the error has several, each alone carries only
    // its share); one family, since all name the same physics.
    const std::string family = prefix + "transmission_j" + J;
    for (const std::string& h : std::vector<std::string>{"1", "2", harmonics}) {
      const bool all = h == harmonics;
      const std::string config =
          "{type: transmission_error, joints: [" + J + "], harmonics: [" + h + "]}";
      out->push_back(Make(config, all ? family : family + "_h" + h, robot,
                          joint + " transmission error" + (all ? "" : " (harmonic " + h + ")"),
                          "a wider range of " + joint + " (at least half a turn)", registry));
      out->back().family = family;
    }
    out->push_back(Make("{type: joint_scale, joints: [" + J + "]}", prefix + "scale_j" + J,
                        robot, joint + " gear ratio error", "a wider range of " + joint,
                        registry));
  }
}

// Per rod pair of a parallel arm (none for a serial one): its parallelogram's skew and its ball
// joints' clearance.
void AddParallelLinkCandidates(const WorkcellRobot& robot, Registry& registry,
                               std::vector<CandidateEffect>* out) {
  const int links = ParallelLinkCount(*robot.model);
  for (int i = 1; i <= links; ++i) {
    const std::string I = std::to_string(i), arm = "arm " + I;
    out->push_back(Make("{type: platform_tilt, arms: [" + I + "]}", robot.name + ".tilt_arm" + I,
                        robot, arm + " parallelogram skew",
                        "poses that turn " + arm + "'s rods further", registry));
    out->push_back(Make("{type: ball_joint_clearance, arms: [" + I + "]}",
                        robot.name + ".clearance_arm" + I, robot, arm + " ball-joint clearance",
                        "poses near the workspace edge, where " + arm + "'s load share changes "
                        "most", registry));
  }
}

// Thermal growth as the recorded temperature drives it, and as a warm-up from a cold start in
// time: a temperature read at the controller or in the room need not follow the arm's own
// warming (on the suite's UR3, a warm-up over time against a temperature ramped linearly was
// named 1 time in 5 with the temperature form alone). One family: both name the arm's thermal
// growth, and the bootstrap counts either as it.
void AddThermalCandidates(const WorkcellRobot& robot, const Recording& recording,
                          Registry& registry, std::vector<CandidateEffect>* out) {
  bool temperatures = false, times = false;
  for (const auto& s : recording.samples) {
    temperatures |= s.temperature_c.has_value();
    times |= s.time_s.has_value();
  }
  const std::string thermal = robot.name + ".thermal";
  if (temperatures || !times) {
    out->push_back(Make("{type: thermal_drift}", thermal, robot, "thermal growth of the arm",
                        "temperatures over a range of several degrees", registry));
  }
  if (times) {
    out->push_back(Make("{type: thermal_drift, model: warmup}",
                        temperatures ? thermal + "_warmup" : thermal, robot,
                        "thermal growth while warming up",
                        "captures from a cold start over an hour", registry));
    out->back().family = thermal;
  }
}

}  // namespace

std::vector<CandidateEffect> DefaultCandidates(const WorkcellProblem& spec,
                                               const Recording& recording,
                                               const DiagnosisOptions& options,
                                               Registry& registry) {
  std::string masses, harmonics = "1, 2";
  for (double m : options.link_masses_kg) {
    masses += (masses.empty() ? "" : ", ") + std::to_string(m);
  }
  for (int h : options.gear_harmonics) {
    if (h > 2) harmonics += ", " + std::to_string(h);
  }
  std::vector<CandidateEffect> out;
  for (const auto& robot : spec.robots) {
    AddJointCandidates(robot, masses, harmonics, registry, &out);
    AddParallelLinkCandidates(robot, registry, &out);
    AddThermalCandidates(robot, recording, registry, &out);
  }
  AddCameraCandidates(spec, recording, options.group_candidates, registry, &out);
  return out;
}

}  // namespace cellmetry
