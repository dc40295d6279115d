// DeltaModel's non-template parts (delta_model.h): its parameters, the rods' directions
// (ParallelLinks), and why a pose or a point is out of reach, in words.
#include "delta_model.h"

#include <cstdio>
#include <sstream>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/exact_number.h"

namespace cellmetry::delta {
namespace {

std::string Format(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char text[256];
  std::snprintf(text, sizeof(text), format, a, b, c, d);
  return text;
}

}  // namespace

DeltaModel::DeltaModel(std::array<Arm, kArms> arms, Pose marker_offset, RobotLimits limits)
    : marker_offset_(marker_offset), limits_(std::move(limits)) {
  for (int i = 0; i < kArms; ++i) {
    const double alpha = 2.0 * M_PI * i / kArms;
    sin_alpha_[i] = std::sin(alpha);
    cos_alpha_[i] = std::cos(alpha);
    const std::string arm = "arm" + std::to_string(i + 1) + ".";
    const Arm& a = arms[i];
    parameters_.push_back({arm + "R",
                           "mm",
                           a.R,
                           false,
                           {},
                           {},
                           {},
                           "motor axis to the centre of the base (only R - r is identifiable)",
                           {}});
    parameters_.push_back({arm + "r",
                           "mm",
                           a.r,
                           false,
                           {},
                           {},
                           {},
                           "effector joint to the centre of the effector",
                           {}});
    parameters_.push_back({arm + "L", "mm", a.L, false, {}, {}, {}, "upper arm length", {}});
    parameters_.push_back({arm + "l", "mm", a.l, false, {}, {}, {}, "lower arm (rod) length", {}});
    parameters_.push_back({arm + "homing",
                           "rad",
                           a.homing,
                           false,
                           {},
                           {},
                           {},
                           "homing offset: true motor angle = command + homing",
                           {}});
  }
}

bool DeltaModel::ParallelLinks(const double* q, const double* params,
                               std::vector<ParallelLink>* links) const {
  Transform<double> T_base_flange;
  if (!ForwardT(q, params, &T_base_flange)) return false;
  links->clear();
  for (int i = 0; i < kArms; ++i) {
    const double* arm = params + kParamsPerArm * i;
    const double theta = q[i] + arm[kHoming];
    const double rho = arm[kR] - arm[kSmallR] + arm[kL] * std::cos(theta);
    const Vector3<double> centre(rho * sin_alpha_[i], -rho * cos_alpha_[i],
                                 -arm[kL] * std::sin(theta));
    links->push_back({(centre - T_base_flange.t).normalized(),
                      Eigen::Vector3d(cos_alpha_[i], sin_alpha_[i], 0.0)});
  }
  return true;
}

std::string DeltaModel::ForwardFailure(const double* q, const double* params) const {
  std::array<Vector3<double>, kArms> centre;
  std::array<double, kArms> radius;
  for (int i = 0; i < kArms; ++i) {
    const double* arm = params + kParamsPerArm * i;
    const double theta = q[i] + arm[kHoming];
    const double rho = arm[kR] - arm[kSmallR] + arm[kL] * std::cos(theta);
    centre[i] =
        Vector3<double>(rho * sin_alpha_[i], -rho * cos_alpha_[i], -arm[kL] * std::sin(theta));
    radius[i] = arm[kSmallL];
  }
  double height2 = 0.0;
  Vector3<double> point;
  if (LowerSphereIntersection(centre, radius, &point, &height2)) return "no failure";
  return Format(
      "the three rod spheres do not meet at motor angles (%.4f, %.4f, %.4f) rad "
      "(squared height %.3g mm^2 < 0): the elbows are further apart than the rods reach",
      q[0], q[1], q[2], height2);
}

std::string DeltaModel::InverseFailure(const double* position, const double* params) const {
  for (int i = 0; i < kArms; ++i) {
    double theta = 0.0, ratio = 0.0;
    if (!ArmAngle(i, position, params + kParamsPerArm * i, &theta, &ratio)) {
      return Format("arm %.0f cannot reach (%.2f, %.2f, %.2f) mm", i + 1.0, position[0],
                    position[1], position[2]) +
             Format(" (reach ratio %.3f, must be within [-1, 1])", ratio);
    }
  }
  return "no failure";
}

std::string DeltaModel::CalibratedConfig(const ConfigNode& config, const double* params) const {
  std::ostringstream out;
  out << "type: delta\n";
  CopyTextEntry(config, "name", out);
  CopyTextEntry(config, "description", out);
  out << "units: {length: mm, angle: rad}\n"
      << "arms:                   # arm i turned (i-1)*120 deg about z\n";
  for (int i = 0; i < kArms; ++i) {
    const double* arm = params + kParamsPerArm * i;
    out << "  - {R: " << ExactNumber(arm[kR]) << ", r: " << ExactNumber(arm[kSmallR])
        << ", L: " << ExactNumber(arm[kL]) << ", l: " << ExactNumber(arm[kSmallL])
        << ", homing: " << ExactNumber(arm[kHoming]) << "}\n";
  }
  const Eigen::Vector3d& m = marker_offset_.t;
  out << "marker_offset: {xyz: [" << ExactNumber(m.x()) << ", " << ExactNumber(m.y()) << ", "
      << ExactNumber(m.z()) << "]}\n";
  if (limits_.joint_increment_rad > 0) {
    out << "motor: {increments_per_revolution: "
        << std::lround(2.0 * M_PI / limits_.joint_increment_rad) << "}\n";
  }
  if (!limits_.joint_min_rad.empty()) {
    out << "joint_limits: {min: " << ExactNumber(limits_.joint_min_rad[0])
        << ", max: " << ExactNumber(limits_.joint_max_rad[0]) << "}\n";
  }
  if (limits_.workspace) {
    const CylinderWorkspace& w = *limits_.workspace;
    out << "workspace: {radius: " << ExactNumber(w.radius_mm)
        << ", z_min: " << ExactNumber(w.z_min_mm) << ", z_max: " << ExactNumber(w.z_max_mm)
        << "}\n";
  }
  return out.str();
}

}  // namespace cellmetry::delta
