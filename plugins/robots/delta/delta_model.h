// DeltaModel: a rotary delta arm (three parallelogram arms), as in Poree 2023, appendix 8.1.
//
// Arm i (1-based) lies in a vertical plane turned by alpha_i = (i-1) * 120 deg about the base z
// axis. In that plane (coordinates x', y', z; x' = 0 is the plane):
//   motor axis      F = (0, -R_i, 0)
//   elbow           J = F + (0, -L_i cos(theta_i), -L_i sin(theta_i))    theta > 0 lowers the arm
//   effector joint      E + (0, -r_i, 0), with E the effector centre (the flange)
//   rod             |J - (E + (0, -r_i, 0))| = l_i
// and the motor angle is theta_i = q_i + homing_i (q: the controller's command, rad).
//
// Forward: E is the lower intersection of three spheres, centre J'_i = J_i + (0, r_i, 0) turned
// into the base frame, radius l_i. Solved exactly by trilateration with three distinct radii; the
// report's closed form uses the mean of l_1..l_3 in one term, which is exact only when the three
// rods are equal and cannot be calibrated (a likely reason its forward model did not converge).
// Inverse: per arm, a cos(theta) + z sin(theta) = K in the arm's plane (closed form, report's
// appendix 8.1.1), the elbow-out branch.
//
// Parameters, per arm i: "arm<i>.R", "arm<i>.r", "arm<i>.L", "arm<i>.l" (mm), "arm<i>.homing"
// (rad). Only R_i - r_i enters the kinematics: R and r are not separately identifiable from
// positions, and a calibration reports r as such.
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "cellmetry/model/robot_model.h"

namespace cellmetry::delta {

inline constexpr int kArms = 3;
inline constexpr int kParamsPerArm = 5;
enum Entry { kR = 0, kSmallR = 1, kL = 2, kSmallL = 3, kHoming = 4 };

struct Arm {
  double R = 150.0, r = 40.0, L = 250.0, l = 600.0, homing = 0.0;
};

class DeltaModel : public InvertibleRobotModelFromTemplate<DeltaModel> {
 public:
  DeltaModel(std::array<Arm, kArms> arms, Pose marker_offset, RobotLimits limits);

  int num_joints() const override { return kArms; }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  Pose nominal_tool() const override { return marker_offset_; }
  const RobotLimits& limits() const override { return limits_; }
  std::string ForwardFailure(const double* q, const double* params) const override;
  std::string InverseFailure(const double* position, const double* params) const override;
  int JointOffsetParameter(int joint) const override { return kParamsPerArm * joint + kHoming; }
  // Rod pair i: from the effector joint toward the elbow (J'_i - E, the forward model's sphere
  // centre minus the effector centre), spaced along the motor axis (the arm plane's normal).
  bool ParallelLinks(const double* q, const double* params,
                     std::vector<ParallelLink>* links) const override;
  // The `delta` config with `params` as its arms (mm, rad); marker offset, motor, joint limits
  // and workspace as this model holds them; name and description kept. A delta arm is no serial
  // chain (AsSerialChain stays false): its motors do not carry each other.
  std::string CalibratedConfig(const ConfigNode& config, const double* params) const override;

  template <typename T>
  bool ForwardT(const double* q, const T* params, Transform<T>* T_base_flange) const {
    std::array<Vector3<T>, kArms> centre;
    std::array<T, kArms> radius;
    for (int i = 0; i < kArms; ++i) {
      const T* arm = params + kParamsPerArm * i;
      const T theta = T(q[i]) + arm[kHoming];
      // J'_i: the elbow moved by r_i toward the axis; its distance from the z axis is rho.
      const T rho = arm[kR] - arm[kSmallR] + arm[kL] * cos(theta);
      centre[i] = Vector3<T>(rho * sin_alpha_[i], -rho * cos_alpha_[i], -arm[kL] * sin(theta));
      radius[i] = arm[kSmallL];
    }
    Vector3<T> position;
    if (!LowerSphereIntersection(centre, radius, &position, nullptr)) return false;
    T_base_flange->R.setIdentity();
    T_base_flange->t = position;
    return true;
  }

  template <typename T>
  bool InverseT(const T* position, const T* params, T* q) const {
    for (int i = 0; i < kArms; ++i) {
      if (!ArmAngle(i, position, params + kParamsPerArm * i, &q[i], nullptr)) return false;
      q[i] -= params[kParamsPerArm * i + kHoming];
    }
    return true;
  }

  // The point where three spheres meet, the one with the lower z; false (with the squared
  // height that came out negative, in *height2) where they do not meet.
  template <typename T>
  static bool LowerSphereIntersection(const std::array<Vector3<T>, 3>& c, const std::array<T, 3>& r,
                                      Vector3<T>* point, double* height2) {
    using std::sqrt;
    // Frame at c0: ex toward c1, ey in the plane of the three centres, ez normal to it.
    Vector3<T> ex = c[1] - c[0];
    const T d = ex.norm();
    ex /= d;
    const Vector3<T> c02 = c[2] - c[0];
    const T i = ex.dot(c02);
    Vector3<T> ey = c02 - i * ex;
    const T j = ey.norm();
    if (!(d > T(1e-9)) || !(j > T(1e-9))) return false;  // coincident or collinear centres
    ey /= j;
    const Vector3<T> ez = ex.cross(ey);
    const T x = (r[0] * r[0] - r[1] * r[1] + d * d) / (T(2) * d);
    const T y = (r[0] * r[0] - r[2] * r[2] + i * i + j * j) / (T(2) * j) - (i / j) * x;
    const T z2 = r[0] * r[0] - x * x - y * y;
    if (height2) *height2 = Scalar(z2);
    if (!(z2 > T(0))) return false;
    const T z = sqrt(z2);
    const Vector3<T> base = c[0] + x * ex + y * ey;
    *point = ez.z() > T(0) ? Vector3<T>(base - z * ez) : Vector3<T>(base + z * ez);
    return true;
  }

 private:
  // Motor angle theta of arm `i` that puts the effector centre at `position` (base frame);
  // false where the arm cannot reach, with |K| / rho0 (> 1) in *reach_ratio.
  template <typename T>
  bool ArmAngle(int i, const T* position, const T* arm, T* theta, double* reach_ratio) const {
    using std::acos;
    using std::atan2;
    using std::sqrt;
    // The point in the arm's plane (turned by -alpha_i).
    const T x = position[0] * cos_alpha_[i] + position[1] * sin_alpha_[i];
    const T y = -position[0] * sin_alpha_[i] + position[1] * cos_alpha_[i];
    const T z = position[2];
    const T a = arm[kR] - arm[kSmallR] + y;
    const T K = (arm[kSmallL] * arm[kSmallL] - x * x - arm[kL] * arm[kL] - a * a - z * z) /
                (T(2) * arm[kL]);
    const T rho0 = sqrt(a * a + z * z);
    if (reach_ratio) *reach_ratio = Scalar(K / rho0);
    if (!(K < rho0) || !(K > -rho0)) return false;
    *theta = atan2(z, a) + acos(K / rho0);
    return true;
  }

  template <typename T>
  static double Scalar(const T& value) {
    if constexpr (std::is_same_v<T, double>) {
      return value;
    } else {
      return value.a;
    }
  }

  std::vector<Parameter> parameters_;
  Pose marker_offset_;
  RobotLimits limits_;
  std::array<double, kArms> sin_alpha_{}, cos_alpha_{};
};

}  // namespace cellmetry::delta
