// The facts effects depend on (effect_context.h): gathered per sample once before any fit, handed
// to an effect as its context, and what a candidate needs that the recording lacks.
#include "cellmetry/model/effect_context.h"

#include <cmath>

namespace cellmetry {
namespace {

// d p_flange / d q (mm/rad) by central differences; no columns where the model has no pose.
Eigen::Matrix3Xd FlangeJacobian(const RobotModel& model, const std::vector<double>& q,
                                const std::vector<double>& params) {
  constexpr double kStep = 1e-6;  // rad: ~1e-9 relative error for lengths of a metre
  Eigen::Matrix3Xd J(3, q.size());
  std::vector<double> moved = q;
  for (size_t j = 0; j < q.size(); ++j) {
    Pose plus, minus;
    moved[j] = q[j] + kStep;
    const bool up = model.Forward(moved.data(), params.data(), &plus);
    moved[j] = q[j] - kStep;
    const bool down = model.Forward(moved.data(), params.data(), &minus);
    moved[j] = q[j];
    if (!up || !down) return Eigen::Matrix3Xd(3, 0);
    J.col(j) = (plus.t - minus.t) / (2 * kStep);
  }
  return J;
}

}  // namespace

SampleFacts GeometricFacts(const RobotModel& model, const std::vector<double>& nominal_params,
                           const std::vector<double>& q) {
  SampleFacts f;
  f.q = q;
  if (!model.JointFrames(q.data(), nominal_params.data(), &f.T_base_joint)) {
    f.T_base_joint.clear();
    f.flange_jacobian_mm = FlangeJacobian(model, q, nominal_params);
  }
  if (!model.ParallelLinks(q.data(), nominal_params.data(), &f.links)) f.links.clear();
  return f;
}

std::vector<SampleFacts> GatherSampleFacts(const Recording& recording, const std::string& robot,
                                           const RobotModel& model,
                                           const std::vector<double>& nominal_params) {
  std::vector<SampleFacts> facts(recording.samples.size());
  const int n = model.num_joints();
  std::vector<double> previous;
  std::vector<int> approach(n, 0);
  for (size_t i = 0; i < recording.samples.size(); ++i) {
    const Sample& sample = recording.samples[i];
    if (sample.robot != robot) continue;
    if (!previous.empty()) {
      for (int j = 0; j < n; ++j) {
        const double move = sample.q[j] - previous[j];
        if (std::abs(move) > 1e-9) approach[j] = move > 0 ? 1 : -1;
      }
    }
    previous = sample.q;
    SampleFacts& f = facts[i];
    f = GeometricFacts(model, nominal_params, sample.q);
    f.approach = approach;
    f.time_s = sample.time_s.value_or(NAN);
    f.temperature_c = sample.temperature_c.value_or(NAN);
    f.payload_kg = sample.payload_kg.value_or(0.0);
  }
  return facts;
}

EffectContext ContextOf(const SampleFacts& facts, const Eigen::Vector3d& gravity_base,
                        const std::string& camera) {
  EffectContext context;
  context.num_joints = static_cast<int>(facts.q.size());
  context.q = facts.q.data();
  context.approach = facts.approach.data();
  context.T_base_joint = &facts.T_base_joint;
  context.links = &facts.links;
  context.flange_jacobian_mm = &facts.flange_jacobian_mm;
  context.gravity_base = gravity_base;
  context.time_s = facts.time_s;
  context.temperature_c = facts.temperature_c;
  context.payload_kg = facts.payload_kg;
  context.camera = camera;
  return context;
}

std::string MissingFacts(const EffectNeeds& needs, const std::vector<SampleFacts>& facts) {
  bool frames = false, links = false, time = false, temperature = false;
  std::vector<bool> up, down;
  for (const auto& f : facts) {
    if (f.q.empty()) continue;
    frames |= !f.T_base_joint.empty() || f.flange_jacobian_mm.cols() > 0;
    links |= !f.links.empty();
    time |= std::isfinite(f.time_s);
    temperature |= std::isfinite(f.temperature_c);
    up.resize(f.approach.size()), down.resize(f.approach.size());
    for (size_t j = 0; j < f.approach.size(); ++j) {
      up[j] = up[j] || f.approach[j] > 0;
      down[j] = down[j] || f.approach[j] < 0;
    }
  }
  if (needs.joint_frames && !frames) return "a robot model with joint frames (gravity torques)";
  if (needs.parallel_links && !links) return "a parallel arm (a delta's rods)";
  if (needs.time && !time) return "capture times (samples.csv column t)";
  if (needs.temperature && !temperature) return "temperatures (samples.csv column temperature)";
  if (needs.approach) {
    bool both = false;
    for (size_t j = 0; j < up.size(); ++j) both |= up[j] && down[j];
    if (!both) return "moves into poses from both directions";
  }
  return "";
}

}  // namespace cellmetry
