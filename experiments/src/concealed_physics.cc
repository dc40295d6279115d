#include "cellmetry/experiments/concealed_physics.h"

#include <algorithm>
#include <cmath>

#include "cellmetry/basics/error.h"

namespace cellmetry {
namespace {

// Gravity torque on `joint` of masses spread along each link (five points per link) and a point
// payload at the flange (N m).
double DistributedTorque(const std::vector<Pose>& frames, const std::vector<double>& masses,
                         double payload_kg, const Eigen::Vector3d& gravity, int joint) {
  const int n = static_cast<int>(frames.size()) - 1;
  const Eigen::Vector3d origin = 1e-3 * frames[joint].t, axis = frames[joint].R.col(2);
  double torque = 0.0;
  auto add = [&](const Eigen::Vector3d& p_mm, double m) {
    torque += (1e-3 * p_mm - origin).cross(m * gravity).dot(axis);
  };
  for (int k = joint; k < n; ++k) {
    const double m = k < static_cast<int>(masses.size()) ? masses[k] : 1.0;
    for (double f : {0.1, 0.3, 0.5, 0.7, 0.9}) {
      add(frames[k].t + f * (frames[k + 1].t - frames[k].t), m / 5.0);
    }
  }
  add(frames[n].t, payload_kg);
  return torque;
}

// The gravity torque on the physics' joint in every sample of its robot (0 elsewhere), and the
// largest of them.
std::vector<double> JointTorques(const ConcealedPhysics& c, const Recording& recording,
                                 const std::vector<SampleFacts>& facts,
                                 const Eigen::Vector3d& gravity, double* tau_max) {
  std::vector<double> torque(facts.size(), 0.0);
  *tau_max = 0.0;
  for (size_t i = 0; i < facts.size(); ++i) {
    if (recording.samples[i].robot != c.robot || facts[i].T_base_joint.empty()) continue;
    torque[i] = DistributedTorque(facts[i].T_base_joint, c.link_masses_kg, facts[i].payload_kg,
                                  gravity, c.joint);
    *tau_max = std::max(*tau_max, std::abs(torque[i]));
  }
  return torque;
}

std::vector<DisturbanceAction> DistributedCompliance(const ConcealedPhysics& c,
                                                     const Recording& recording,
                                                     const std::vector<SampleFacts>& facts,
                                                     const Eigen::Vector3d& gravity) {
  double tau_max = 0.0;
  const std::vector<double> torque = JointTorques(c, recording, facts, gravity, &tau_max);
  std::vector<DisturbanceAction> out(facts.size());
  for (size_t i = 0; i < facts.size(); ++i) {
    if (recording.samples[i].robot != c.robot) continue;
    out[i].dq.assign(facts[i].q.size(), 0.0);
    const double stiff = tau_max > 0 ? 1.0 - c.stiffening * std::abs(torque[i]) / tau_max : 1.0;
    out[i].dq[c.joint] = c.magnitude * torque[i] * stiff;
  }
  return out;
}

// The joint sits inside its play where its last push left it: a move drags it against one side
// of the play, but friction lets short moves take up only part of it (1 - exp(-|move| / 0.3
// rad)), and a move that does not cross the play leaves it where it was.
std::vector<DisturbanceAction> DeadZoneBacklash(const ConcealedPhysics& c,
                                                const Recording& recording,
                                                const std::vector<SampleFacts>& facts) {
  std::vector<DisturbanceAction> out(facts.size());
  const double half = 0.5 * c.magnitude;
  std::optional<double> actual, previous;
  for (size_t i = 0; i < facts.size(); ++i) {
    if (recording.samples[i].robot != c.robot) continue;
    const double q = facts[i].q[c.joint];
    if (!actual) actual = q - half;  // arrived from below
    const double move = previous ? q - *previous : 0.0;
    const double lag = half * (1.0 - std::exp(-std::abs(move) / 0.3));
    if (q - *actual > lag) *actual = q - lag;
    if (*actual - q > lag) *actual = q + lag;
    previous = q;
    out[i].dq.assign(facts[i].q.size(), 0.0);
    out[i].dq[c.joint] = *actual - q;
  }
  return out;
}

// Gravity holds the joint against one flank of its play wherever its torque beats the friction
// (a `hold` share of the largest torque the run puts on it); below that, the joint stays where
// its last move left it, lagging on the side it came from. Masses spread along the links, as
// DistributedCompliance takes them.
std::vector<DisturbanceAction> GravityBacklash(const ConcealedPhysics& c,
                                               const Recording& recording,
                                               const std::vector<SampleFacts>& facts,
                                               const Eigen::Vector3d& gravity) {
  double tau_max = 0.0;
  const std::vector<double> torque = JointTorques(c, recording, facts, gravity, &tau_max);
  std::vector<DisturbanceAction> out(facts.size());
  const double half = 0.5 * c.magnitude;
  double lag = -half;  // arrived from below
  std::optional<double> previous;
  for (size_t i = 0; i < facts.size(); ++i) {
    if (recording.samples[i].robot != c.robot) continue;
    const double q = facts[i].q[c.joint];
    if (std::abs(torque[i]) > c.hold * tau_max) {
      lag = torque[i] > 0 ? half : -half;
    } else if (previous && q != *previous) {
      lag = q > *previous ? -half : half;
    }
    previous = q;
    out[i].dq.assign(facts[i].q.size(), 0.0);
    out[i].dq[c.joint] = lag;
  }
  return out;
}

std::vector<DisturbanceAction> GearHarmonics(const ConcealedPhysics& c, const Recording& recording,
                                             const std::vector<SampleFacts>& facts) {
  static const double kWeights[] = {1.0, 0.6, 0.4, 0.3, 0.2};
  static const double kPhases[] = {0.3, 1.1, 2.0, 2.7, 0.9};
  std::vector<DisturbanceAction> out(facts.size());
  for (size_t i = 0; i < facts.size(); ++i) {
    if (recording.samples[i].robot != c.robot) continue;
    out[i].dq.assign(facts[i].q.size(), 0.0);
    for (size_t h = 0; h < c.harmonics.size() && h < 5; ++h) {
      out[i].dq[c.joint] +=
          c.magnitude * kWeights[h] * std::sin(c.harmonics[h] * facts[i].q[c.joint] + kPhases[h]);
    }
  }
  return out;
}

// A lens's coefficients: Brown-Conrady radial k1, k2, k3 and tangential p1, p2 (Brown 1966),
// and the thin prism's s1, s3 (s2 = s4 = 0; Weng, Cohen & Herniou 1992, "Camera calibration
// with distortion models and accuracy evaluation", IEEE PAMI 14): OpenCV's calib3d model.
struct LensCoefficients {
  double k1 = 0, k2 = 0, k3 = 0, p1 = 0, p2 = 0, s1 = 0, s3 = 0;
};

// The distortion of normalized image coordinates (x, y), and the map's Jacobian there.
struct Distorted {
  Eigen::Vector2d xy;
  Eigen::Matrix2d jacobian;
};
Distorted Distort(double x, double y, const LensCoefficients& c) {
  const double r2 = x * x + y * y;
  const double radial = c.k1 * r2 + c.k2 * r2 * r2 + c.k3 * r2 * r2 * r2;
  const double d_radial_d_r2 = c.k1 + 2.0 * c.k2 * r2 + 3.0 * c.k3 * r2 * r2;
  Distorted out;
  out.xy = Eigen::Vector2d(
      x * (1.0 + radial) + 2.0 * c.p1 * x * y + c.p2 * (r2 + 2.0 * x * x) + c.s1 * r2,
      y * (1.0 + radial) + c.p1 * (r2 + 2.0 * y * y) + 2.0 * c.p2 * x * y + c.s3 * r2);
  const double cross = 2.0 * x * y * d_radial_d_r2 + 2.0 * c.p1 * x + 2.0 * c.p2 * y;
  out.jacobian << 1.0 + radial + 2.0 * x * x * d_radial_d_r2 + 2.0 * c.p1 * y + 6.0 * c.p2 * x +
                      2.0 * c.s1 * x,
      cross + 2.0 * c.s1 * y, cross + 2.0 * c.s3 * x,
      1.0 + radial + 2.0 * y * y * d_radial_d_r2 + 6.0 * c.p1 * y + 2.0 * c.p2 * x + 2.0 * c.s3 * y;
  return out;
}

}  // namespace

void ConcealedPhysics::MeasureInCamera(const std::string& cam, Pose* T_cam_target) const {
  if (kind != "lens_distortion" || cam != camera) return;
  const double z = T_cam_target->t.z();
  const Eigen::Vector3d k2_p1_p2 = magnitude * lens_shape, k3_s1_s3 = magnitude * lens_beyond;
  const LensCoefficients lens{magnitude,   k2_p1_p2[0], k3_s1_s3[0], k2_p1_p2[1],
                              k2_p1_p2[2], k3_s1_s3[1], k3_s1_s3[2]};
  const Distorted seen = Distort(T_cam_target->t.x() / z, T_cam_target->t.y() / z, lens);
  const double depth = z / std::sqrt(seen.jacobian.determinant());
  T_cam_target->t = Eigen::Vector3d(seen.xy.x() * depth, seen.xy.y() * depth, depth);
  // The image turns locally by the map's antisymmetric part: so does the board PnP fits to it.
  const double turn = 0.5 * (seen.jacobian(1, 0) - seen.jacobian(0, 1));
  T_cam_target->R = Eigen::AngleAxisd(turn, T_cam_target->t.normalized()) * T_cam_target->R;
}

ConcealedPhysics ReadConcealedPhysics(const ConfigNode& node) {
  node.ExpectKeys({"kind", "robot", "joint", "camera", "magnitude", "link_masses_kg", "stiffening",
                   "hold", "harmonics", "time_constant_s", "direction", "lens_shape",
                   "lens_beyond"});
  ConcealedPhysics c;
  c.kind = node["kind"].AsString();
  static const std::vector<std::string> kinds = {"distributed_compliance",
                                                 "dead_zone_backlash",
                                                 "gravity_backlash",
                                                 "gear_harmonics",
                                                 "warmup",
                                                 "camera_bump",
                                                 "lens_distortion"};
  if (std::find(kinds.begin(), kinds.end(), c.kind) == kinds.end()) {
    throw node["kind"].Error("unknown concealed physics '" + c.kind + "'",
                             "Use distributed_compliance, dead_zone_backlash, gravity_backlash, "
                             "gear_harmonics, warmup, camera_bump or lens_distortion");
  }
  c.robot = node.GetString("robot", "");
  c.joint = node.GetInt("joint", 1) - 1;
  c.camera = node.GetString("camera", "");
  c.magnitude = node.GetDouble("magnitude", 0.0);  // the physics suite sets it from the SNR
  if (node.Has("link_masses_kg")) c.link_masses_kg = node["link_masses_kg"].AsDoubles();
  c.stiffening = node.GetDouble("stiffening", c.stiffening);
  c.hold = node.GetDouble("hold", c.hold);
  if (!(c.hold >= 0 && c.hold < 1)) {
    throw node["hold"].Error("is a share of the largest torque, in [0, 1)");
  }
  if (node.Has("harmonics")) {
    c.harmonics.clear();
    for (const auto& h : node["harmonics"].Elements()) c.harmonics.push_back(h.AsInt());
  }
  c.time_constant_s = node.GetDouble("time_constant_s", c.time_constant_s);
  if (node.Has("direction")) {
    const auto d = node["direction"].AsDoubles(3);
    c.direction = Eigen::Vector3d(d[0], d[1], d[2]);
  }
  if (node.Has("lens_shape")) {
    const auto k = node["lens_shape"].AsDoubles(3);
    c.lens_shape = Eigen::Vector3d(k[0], k[1], k[2]);
  }
  if (node.Has("lens_beyond")) {
    const auto k = node["lens_beyond"].AsDoubles(3);
    c.lens_beyond = Eigen::Vector3d(k[0], k[1], k[2]);
  }
  return c;
}

std::shared_ptr<const Disturbance> ReadConcealedDisturbance(const ConfigNode& node) {
  return std::make_shared<ConcealedPhysics>(ReadConcealedPhysics(node));
}

std::vector<DisturbanceAction> ConcealedPhysics::Actions(
    const Recording& recording, const std::vector<SampleFacts>& facts,
    const Eigen::Vector3d& gravity_base) const {
  const ConcealedPhysics& c = *this;
  if (c.kind == "distributed_compliance") {
    return DistributedCompliance(c, recording, facts, gravity_base);
  }
  if (c.kind == "dead_zone_backlash") return DeadZoneBacklash(c, recording, facts);
  if (c.kind == "gravity_backlash") return GravityBacklash(c, recording, facts, gravity_base);
  if (c.kind == "gear_harmonics") return GearHarmonics(c, recording, facts);
  std::vector<DisturbanceAction> out(recording.samples.size());
  for (size_t i = 0; i < out.size(); ++i) {
    if (c.kind == "warmup") {
      const auto t = recording.samples[i].time_s;
      if (!t) {
        throw InputError({"", 0, 0}, "warm-up needs sample times",
                         "Add timeline: {seconds_per_sample: ...} to the simulation");
      }
      out[i].flange_scale = c.magnitude * (1.0 - std::exp(-*t / c.time_constant_s));
    } else if (c.kind == "camera_bump" && i >= out.size() / 2) {
      out[i].camera_shift_mm = c.magnitude * c.direction.normalized();
    }
  }
  return out;
}

}  // namespace cellmetry
