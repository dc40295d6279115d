// The physics finder's default candidates (diagnosis.h): the effect library, each effect on one
// joint or camera at a time, so that a finding names the joint or camera.
#include <string>

#include "cellmetry/diagnosis.h"

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
  c.label = label;
  c.data_hint = hint;
  return c;
}

}  // namespace

std::vector<CandidateEffect> DefaultCandidates(const WorkcellProblem& spec,
                                               const Recording& recording,
                                               const std::vector<double>& link_masses_kg,
                                               Registry& registry) {
  std::string masses;
  for (double m : link_masses_kg) masses += (masses.empty() ? "" : ", ") + std::to_string(m);
  std::vector<CandidateEffect> out;
  for (const auto& robot : spec.robots) {
    for (int j = 1; j <= robot.model->num_joints(); ++j) {
      const std::string J = std::to_string(j), joint = "joint " + J;
      const std::string prefix = robot.name + ".";
      out.push_back(Make("{type: joint_compliance, joints: [" + J + "]" +
                             (masses.empty() ? "" : ", link_masses_kg: [" + masses + "]") + "}",
                         prefix + "compliance_j" + J, robot, joint + " compliance", 
                         "poses that load " + joint + " differently (outstretched and folded)",
                         registry));
      out.push_back(Make("{type: backlash, joints: [" + J + "]}", prefix + "backlash_j" + J,
                         robot, joint + " backlash",
                         "moves into poses from both directions on " + joint, registry));
      // One candidate per harmonic: two parameters each, so that a single harmonic does not pay
      // for four (a later round adds the other when it is there too).
      for (const std::string h : {"1", "2"}) {
        out.push_back(Make("{type: transmission_error, joints: [" + J + "], harmonics: [" + h + "]}",
                           prefix + "transmission_j" + J + "_h" + h, robot,
                           joint + " transmission error (harmonic " + h + ")",
                           "a wider range of " + joint + " (at least half a turn)", registry));
      }
      out.push_back(Make("{type: joint_scale, joints: [" + J + "]}", prefix + "scale_j" + J,
                         robot, joint + " gear ratio error", "a wider range of " + joint,
                         registry));
    }
    bool temperatures = false, times = false;
    for (const auto& s : recording.samples) {
      temperatures |= s.temperature_c.has_value();
      times |= s.time_s.has_value();
    }
    if (temperatures || !times) {
      out.push_back(Make("{type: thermal_drift}", robot.name + ".thermal", robot,
                         "thermal growth of the arm",
                         "temperatures over a range of several degrees", registry));
    } else {
      out.push_back(Make("{type: thermal_drift, model: warmup}", robot.name + ".thermal", robot,
                         "thermal growth while warming up",
                         "captures from a cold start over an hour", registry));
    }
  }
  for (const auto& camera : recording.cameras) {
    out.push_back(Make("{type: depth_bias, cameras: [" + camera + "]}", "camera.depth_" + camera,
                       spec.robots.front(), camera + " depth bias",
                       "targets at more varied distances from " + camera, registry));
  }
  return out;
}

}  // namespace cellmetry
