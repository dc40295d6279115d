// Registers the effect library: joint_compliance, link_bending, base_tilt, backlash,
// transmission_error, joint_scale, joint_coupling, thermal_drift, depth_bias, detection_bias,
// target_scale, camera_intrinsics, target_tilt, world_frame, platform_tilt, ball_joint_clearance
// (one header each says its physics), and the physics finder's candidates among them
// (default_candidates.h).
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "cellmetry/registry/registry.h"
#include "backlash.h"
#include "ball_joint_clearance.h"
#include "base_tilt.h"
#include "camera_intrinsics.h"
#include "default_candidates.h"
#include "depth_bias.h"
#include "detection_bias.h"
#include "joint_compliance.h"
#include "joint_coupling.h"
#include "joint_scale.h"
#include "joint_selection.h"
#include "link_bending.h"
#include "platform_tilt.h"
#include "target_scale.h"
#include "target_tilt.h"
#include "thermal_drift.h"
#include "transmission_error.h"

namespace cellmetry::effects {
namespace {

std::unique_ptr<Effect> CreateCompliance(const ConfigNode& config, const RobotModel& robot) {
  config.ExpectKeys({"type", "joints", "link_masses_kg"});
  std::vector<double> masses(robot.num_joints(), 1.0);
  if (config.Has("link_masses_kg")) masses = config["link_masses_kg"].AsDoubles(robot.num_joints());
  return std::make_unique<JointCompliance>(SelectJoints(config, robot), masses);
}

std::unique_ptr<Effect> CreateBending(const ConfigNode& config, const RobotModel& robot) {
  config.ExpectKeys({"type", "links", "link_masses_kg"});
  std::vector<int> links;
  if (config.Has("links")) {
    for (const auto& node : config["links"].Elements()) links.push_back(SelectJoint(node, robot));
    if (links.empty()) throw config["links"].Error("lists no link", "e.g. links: [2, 3]");
  } else {
    for (int i = 0; i < robot.num_joints(); ++i) links.push_back(i);
  }
  std::vector<double> masses(robot.num_joints(), 1.0);
  if (config.Has("link_masses_kg")) masses = config["link_masses_kg"].AsDoubles(robot.num_joints());
  return std::make_unique<LinkBending>(links, masses);
}

std::unique_ptr<Effect> CreateBaseTilt(const ConfigNode& config, const RobotModel& robot) {
  config.ExpectKeys({"type", "pivot_mm", "link_masses_kg"});
  std::vector<double> masses(robot.num_joints(), 1.0);
  if (config.Has("link_masses_kg")) masses = config["link_masses_kg"].AsDoubles(robot.num_joints());
  const double pivot_mm = config.GetDouble("pivot_mm", 0.0);
  if (!std::isfinite(pivot_mm)) {
    throw config["pivot_mm"].Error("must be a distance (mm) below the base frame's origin");
  }
  return std::make_unique<BaseTilt>(masses, pivot_mm);
}

std::unique_ptr<Effect> CreateBacklash(const ConfigNode& config, const RobotModel& robot) {
  config.ExpectKeys({"type", "joints", "held_by", "link_masses_kg", "hold_nm"});
  const std::string held_by = config.GetString("held_by", "approach");
  if (held_by != "approach" && held_by != "gravity") {
    throw config["held_by"].Error("unknown backlash hold '" + held_by + "'",
                                  "Use approach (the last move) or gravity");
  }
  std::vector<double> masses;
  if (held_by == "gravity") {
    masses.assign(robot.num_joints(), 1.0);
    if (config.Has("link_masses_kg")) {
      masses = config["link_masses_kg"].AsDoubles(robot.num_joints());
    }
  } else {
    for (const char* key : {"link_masses_kg", "hold_nm"}) {
      if (config.Has(key)) {
        throw config[key].Error("only a backlash held by gravity has it",
                                "Add held_by: gravity, or remove " + std::string(key));
      }
    }
  }
  const double hold_nm = config.GetDouble("hold_nm", 2.0);
  if (!(hold_nm > 0)) throw config["hold_nm"].Error("must be a positive torque (N m)");
  return std::make_unique<Backlash>(SelectJoints(config, robot), masses, hold_nm);
}

std::unique_ptr<Effect> CreateTransmission(const ConfigNode& config, const RobotModel& robot) {
  config.ExpectKeys({"type", "joints", "harmonics"});
  std::vector<int> harmonics = {1, 2};
  if (config.Has("harmonics")) {
    harmonics.clear();
    for (const auto& node : config["harmonics"].Elements()) {
      if (node.AsInt() < 1)
        throw node.Error("a harmonic is a whole number of cycles per turn, >= 1");
      harmonics.push_back(node.AsInt());
    }
  }
  return std::make_unique<TransmissionError>(SelectJoints(config, robot), harmonics);
}

std::unique_ptr<Effect> CreateScale(const ConfigNode& config, const RobotModel& robot) {
  config.ExpectKeys({"type", "joints"});
  return std::make_unique<JointScale>(SelectJoints(config, robot));
}

std::unique_ptr<Effect> CreateCoupling(const ConfigNode& config, const RobotModel& robot) {
  config.ExpectKeys({"type", "joints", "from"});
  if (!config.Has("joints") || !config.Has("from")) {
    throw config.Error("names the driven joints and the driving one", "e.g. joints: [6], from: 5");
  }
  const std::vector<int> driven = SelectJoints(config, robot);
  const int from = SelectJoint(config["from"], robot);
  if (std::find(driven.begin(), driven.end(), from) != driven.end()) {
    throw config["from"].Error("a joint does not couple to itself", "e.g. joints: [6], from: 5");
  }
  return std::make_unique<JointCoupling>(driven, from);
}

std::unique_ptr<Effect> CreateThermal(const ConfigNode& config, const RobotModel&) {
  config.ExpectKeys({"type", "model", "reference_c", "time_constant_s"});
  const std::string model = config.GetString("model", "temperature");
  if (model != "temperature" && model != "warmup") {
    throw config["model"].Error("unknown thermal model '" + model + "'",
                                "Use temperature or warmup");
  }
  const double tau = config.GetDouble("time_constant_s", 1800.0);
  if (!(tau > 0)) throw config["time_constant_s"].Error("must be positive");
  return std::make_unique<ThermalDrift>(
      model == "temperature" ? ThermalDrift::Model::kTemperature : ThermalDrift::Model::kWarmup,
      config.GetDouble("reference_c", 20.0), tau);
}

std::unique_ptr<Effect> CreateDepthBias(const ConfigNode& config, const RobotModel&) {
  config.ExpectKeys({"type", "cameras", "terms"});
  std::vector<std::string> cameras;
  for (const auto& node : config["cameras"].Elements()) cameras.push_back(node.AsString());
  if (cameras.empty()) throw config["cameras"].Error("lists no camera", "e.g. cameras: [cam1]");
  bool scale = true, quadratic = true, tilt = false;
  if (config.Has("terms")) {
    scale = quadratic = false;
    for (const auto& node : config["terms"].Elements()) {
      const std::string term = node.AsString();
      if (term == "scale") {
        scale = true;
      } else if (term == "quadratic") {
        quadratic = true;
      } else if (term == "tilt") {
        tilt = true;
      } else {
        throw node.Error("unknown depth term '" + term + "'", "Use scale, quadratic and/or tilt");
      }
    }
  }
  return std::make_unique<DepthBias>(cameras, scale, quadratic, tilt);
}

std::unique_ptr<Effect> CreateDetectionBias(const ConfigNode& config, const RobotModel&) {
  config.ExpectKeys({"type", "cameras", "targets", "prior_mm", "prior_rad", "frame"});
  const std::string frame = config.GetString("frame", "camera");
  if (frame != "camera" && frame != "target") {
    throw config["frame"].Error("unknown frame '" + frame + "'", "Use camera or target");
  }
  std::vector<std::string> cameras, targets;
  for (const auto& node : config["cameras"].Elements()) cameras.push_back(node.AsString());
  for (const auto& node : config["targets"].Elements()) targets.push_back(node.AsString());
  if (cameras.empty() || targets.empty()) {
    throw config.Error("needs cameras: and targets:", "e.g. cameras: [cam1], targets: [tool]");
  }
  Eigen::Vector3d prior(0.1, 0.1, 0.3);
  if (config.Has("prior_mm")) {
    const ConfigNode node = config["prior_mm"];
    const auto values =
        node.IsSequence() ? node.AsDoubles(3) : std::vector<double>(3, node.AsDouble());
    prior = Eigen::Vector3d(values[0], values[1], values[2]);
    if (!(prior.minCoeff() > 0)) throw node.Error("must be positive");
  }
  const double prior_rad = config.GetDouble("prior_rad", 0.5e-3);
  if (!(prior_rad > 0)) throw config["prior_rad"].Error("must be positive");
  return std::make_unique<DetectionBias>(cameras, targets, prior, prior_rad, frame == "target");
}

// A list of names under `key`, at least one.
std::vector<std::string> Names(const ConfigNode& config, const std::string& key,
                               const std::string& example) {
  std::vector<std::string> names;
  for (const auto& node : config[key].Elements()) names.push_back(node.AsString());
  if (names.empty())
    throw config[key].Error("lists no name", "e.g. " + key + ": [" + example + "]");
  return names;
}

std::unique_ptr<Effect> CreateTargetScale(const ConfigNode& config, const RobotModel&) {
  config.ExpectKeys({"type", "targets", "shared"});
  return std::make_unique<TargetScale>(Names(config, "targets", "tool"),
                                       config.GetBool("shared", false));
}

std::unique_ptr<Effect> CreateIntrinsics(const ConfigNode& config, const RobotModel&) {
  config.ExpectKeys({"type", "cameras", "terms"});
  IntrinsicsTerms terms;
  if (config.Has("terms")) {
    terms = IntrinsicsTerms{false, false, false, false, false};
    for (const auto& node : config["terms"].Elements()) {
      const std::string term = node.AsString();
      if (term == "focal") {
        terms.focal = true;
      } else if (term == "principal") {
        terms.principal = true;
      } else if (term == "radial") {
        terms.radial = true;
      } else if (term == "k2") {
        terms.k2 = true;
      } else if (term == "tangential") {
        terms.tangential = true;
      } else {
        throw node.Error("unknown intrinsics term '" + term + "'",
                         "Use focal, principal, radial, k2 and/or tangential");
      }
    }
  }
  return std::make_unique<CameraIntrinsics>(Names(config, "cameras", "cam1"), terms);
}

std::unique_ptr<Effect> CreateTargetTilt(const ConfigNode& config, const RobotModel&) {
  config.ExpectKeys({"type", "targets"});
  return std::make_unique<TargetTilt>(Names(config, "targets", "tool"), /*world=*/false);
}

std::unique_ptr<Effect> CreateWorldFrame(const ConfigNode& config, const RobotModel&) {
  config.ExpectKeys({"type", "target", "axes"});
  bool turn = false;
  if (config.Has("axes")) {
    std::vector<std::string> axes;
    for (const auto& node : config["axes"].Elements()) axes.push_back(node.AsString());
    if (axes == std::vector<std::string>{"x", "y", "z"}) {
      turn = true;
    } else if (axes != std::vector<std::string>{"x", "y"}) {
      throw config["axes"].Error("world_frame turns about [x, y] or [x, y, z]",
                                 "Use [x, y, z] only where every base's rotation is given");
    }
  }
  return std::make_unique<TargetTilt>(std::vector<std::string>{config.GetString("target", "world")},
                                      /*world=*/true, turn);
}

// `arms: [1, 3]` (1-based; default all three) of a parallel arm; an error for a serial arm.
std::vector<int> SelectArms(const ConfigNode& config, const RobotModel& robot) {
  std::vector<ParallelLink> links;
  const std::vector<double> q(robot.num_joints(), 0.0);
  std::vector<double> nominal;
  for (const auto& p : robot.parameters()) nominal.push_back(p.nominal);
  if (!robot.ParallelLinks(q.data(), nominal.data(), &links)) {
    throw config["type"].Error("'" + config["type"].AsString() +
                                   "' acts on a parallel arm's "
                                   "links (a delta arm); this robot model has none",
                               "Use it with a delta robot, or remove it");
  }
  std::vector<int> arms;
  if (!config.Has("arms")) {
    for (size_t i = 0; i < links.size(); ++i) arms.push_back(static_cast<int>(i));
    return arms;
  }
  for (const auto& node : config["arms"].Elements()) {
    const int arm = node.AsInt();
    if (arm < 1 || arm > static_cast<int>(links.size())) {
      throw node.Error("no arm " + std::to_string(arm) + " (the robot has " +
                       std::to_string(links.size()) + ")");
    }
    arms.push_back(arm - 1);
  }
  return arms;
}

std::unique_ptr<Effect> CreatePlatformTilt(const ConfigNode& config, const RobotModel& robot) {
  config.ExpectKeys({"type", "arms"});
  return std::make_unique<PlatformTilt>(SelectArms(config, robot));
}

std::unique_ptr<Effect> CreateClearance(const ConfigNode& config, const RobotModel& robot) {
  config.ExpectKeys({"type", "arms"});
  return std::make_unique<BallJointClearance>(SelectArms(config, robot));
}

PluginInfo Info(std::string name, std::string description, std::vector<OptionDoc> options) {
  PluginInfo info;
  info.kind = PluginKind::kEffect;
  info.name = std::move(name);
  info.description = std::move(description);
  info.options = std::move(options);
  return info;
}

}  // namespace
}  // namespace cellmetry::effects

CELLMETRY_PLUGIN_ENTRY(registry) {
  namespace fx = cellmetry::effects;
  using fx::Info;
  const cellmetry::OptionDoc joints{"joints", "", "all", "1-based joints it acts on"};
  registry->AddEffect(Info("joint_compliance", "joints giving under gravity: dq_i = c_i tau_g,i(q)",
                           {joints, {"link_masses_kg", "kg", "1 per link", "lumped link masses"}}),
                      &fx::CreateCompliance);
  registry->AddEffect(
      Info("link_bending",
           "links bending as beams under gravity: the flange turns and moves by c_i times the "
           "bending moment integrated along link i",
           {{"links", "", "all", "1-based links it acts on (link i: joint i's origin to the next)"},
            {"link_masses_kg", "kg", "1 per link", "lumped link masses"}}),
      &fx::CreateBending);
  registry->AddEffect(
      Info("base_tilt",
           "the mounting tilting under the arm's overturning moment: the arm turns by c M_h "
           "about a pivot below the base frame",
           {{"pivot_mm", "mm", "0", "how far below the base frame's origin the mounting turns"},
            {"link_masses_kg", "kg", "1 per link", "lumped link masses"}}),
      &fx::CreateBaseTilt);
  registry->AddEffect(
      Info("backlash",
           "gear play: dq_i = -b_i/2 * (direction of the last move), or with "
           "held_by: gravity, b_i/2 * tanh(tau_g,i / hold_nm)",
           {joints,
            {"held_by", "", "approach", "approach | gravity"},
            {"link_masses_kg", "kg", "1 per link", "lumped link masses (gravity)"},
            {"hold_nm", "N m", "2", "torque the joint's friction holds (gravity)"}}),
      &fx::CreateBacklash);
  registry->AddEffect(
      Info("transmission_error",
           "gear error repeating with the joint: dq_i = s sin(h q_i) + c cos(h q_i)",
           {joints, {"harmonics", "", "[1, 2]", "cycles per joint revolution"}}),
      &fx::CreateTransmission);
  registry->AddEffect(Info("joint_scale", "gear ratio error: dq_i = s_i q_i", {joints}),
                      &fx::CreateScale);
  registry->AddEffect(Info("joint_coupling", "joints turning with another: dq_i = k_i q_from",
                           {{"joints", "", "", "1-based joints it turns"},
                            {"from", "", "", "1-based joint whose reading turns them"}}),
                      &fx::CreateCoupling);
  registry->AddEffect(Info("thermal_drift",
                           "links growing with temperature or warm-up time (flange distance scale)",
                           {{"model", "", "temperature", "temperature | warmup"},
                            {"reference_c", "degC", "20", "temperature of the nominal geometry"},
                            {"time_constant_s", "s", "1800", "warm-up time constant"}}),
                      &fx::CreateThermal);
  registry->AddEffect(
      Info("depth_bias",
           "camera distance error: p' = p (1 + a + b Z + t_x X/Z + t_y Y/Z) per camera",
           {{"cameras", "", "", "cameras it acts on"},
            {"terms", "", "[scale, quadratic]", "which of scale, quadratic, tilt"}}),
      &fx::CreateDepthBias);
  registry->AddEffect(
      Info("detection_bias",
           "a detector's systematic error repeating in one camera's view: p' = p + b",
           {{"cameras", "", "", "cameras it acts on"},
            {"targets", "", "", "targets it acts on"},
            {"prior_mm", "mm", "[0.1, 0.1, 0.3]", "expected size along x, y, z (Gaussian prior)"},
            {"prior_rad", "rad", "0.5e-3", "expected rotation error (prior)"},
            {"frame", "", "camera", "camera | target: the axes it is fixed in"}}),
      &fx::CreateDetectionBias);
  registry->AddEffect(
      Info("target_scale", "a target printed at another size: p' = p (1 + s) in every camera",
           {{"targets", "", "", "targets it acts on"},
            {"shared", "", "false", "true: one scale for all of them (boards from one printer)"}}),
      &fx::CreateTargetScale);
  registry->AddEffect(Info("camera_intrinsics",
                           "a camera's focal length, principal point or lens distortion off, "
                           "as PnP passes it to the measured pose",
                           {{"cameras", "", "", "cameras it acts on"},
                            {"terms", "", "[focal, principal, radial]",
                             "which terms: focal, principal, radial (k1), k2, tangential"}}),
                      &fx::CreateIntrinsics);
  registry->AddEffect(
      Info("target_tilt", "a pose estimator's tilt of a target: R' = R exp([t_x, t_y, 0])",
           {{"targets", "", "", "targets it acts on"}}),
      &fx::CreateTargetTilt);
  registry->AddEffect(
      Info("world_frame", "the world tag turned from the frame the placement was measured in",
           {{"target", "", "world", "the world target"},
            {"axes", "", "[x, y]", "[x, y] (tilt) or [x, y, z] (and turn)"}}),
      &fx::CreateWorldFrame);
  const cellmetry::OptionDoc arms{"arms", "", "all", "1-based arms of a delta it acts on"};
  registry->AddEffect(
      Info("platform_tilt",
           "delta parallelograms out of true: the platform tilts, (e_i x u_i).w = k_i", {arms}),
      &fx::CreatePlatformTilt);
  registry->AddEffect(Info("ball_joint_clearance",
                           "delta ball-joint play along the rod force: u_i.dp = -c_i s_i", {arms}),
                      &fx::CreateClearance);
  registry->AddCandidateOffer(&fx::OfferCandidates);
}
