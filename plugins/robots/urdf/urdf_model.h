// UrdfModel: a serial arm read from a URDF (urdf_chain.h), calibrated through its joint origins.
//
// Movable joint i maps its frame into the previous one as
//
//   O_i = T_previous_parent_i Trans(x_i, y_i, z_i) R_parent_joint_i RPY(roll_i, pitch_i, yaw_i)
//   A_i = O_i Rot(axis_i, q_i + offset_i),     T_base_flange = A_1 ... A_n T_last_joint_tip
//
// where (x, y, z) is the joint's <origin xyz> in its parent link (mm; nominal: the URDF's),
// R_parent_joint its <origin rpy>, and RPY(roll, pitch, yaw) = Rz(yaw) Ry(pitch) Rx(roll) (the
// URDF's own convention) a small turn of the joint frame about its own axes after it (rad;
// nominal 0). offset is added to the controller's reading (rad; nominal 0). The flange is the
// tip_link's frame. Parameters, per joint in chain order: "<joint>.x", ".y", ".z", ".roll",
// ".pitch", ".yaw", ".offset", with the URDF's joint names. The parametrisation has no
// singularity near the URDF's geometry, parallel axes included (no common normal to place).
//
// Seven per joint is more than end-effector poses determine (4 per joint between the first and
// the last, as in modified DH); the others are held by convention (Parameter::convention,
// urdf_conventions.h): joint 1's put the base frame, the last joint's offset and its shift along
// its axis the flange frame; for every other joint, a turn about its own axis is its offset's,
// a shift along the previous axis is the previous joint's, and a turn about the previous axis
// (or, where the two axes are parallel, where this axis stands about it) the previous offset's.
//
// A config's `calibrated:` map (parameter name -> value, mm and rad) replaces nominal values: what
// CalibratedConfig writes, so that a calibration becomes the next job's robot on the same URDF.
//
// As a chain of revolute joints about z (serial_chain.h), for exports: with M_i a fixed rotation
// taking z to axis_i, Rot(axis_i, q) = M_i Rz(q) M_i^T, so joint i's origin is
// M_{i-1}^T O_i Rot(axis_i, offset_i) M_i (M_0 = I) and the flange M_n^T T_last_joint_tip.
// Under the URDF's own names (named_chain.h) nothing needs turning: the fixed joints stay as read
// and movable joint i's origin is O_i without T_previous_parent, times Rot(axis_i, offset_i).
#pragma once

#include <string>
#include <vector>

#include "cellmetry/model/robot_model.h"
#include "urdf_chain.h"

namespace cellmetry::urdf_robot {

inline constexpr int kParamsPerJoint = 7;
enum Entry { kX = 0, kY = 1, kZ = 2, kRoll = 3, kPitch = 4, kYaw = 5, kOffset = 6 };

class UrdfModel : public RobotModelFromTemplate<UrdfModel> {
 public:
  explicit UrdfModel(UrdfChain chain);

  const UrdfChain& chain() const { return chain_; }
  int num_joints() const override { return static_cast<int>(chain_.joints.size()); }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  int JointOffsetParameter(int joint) const override { return kParamsPerJoint * joint + kOffset; }
  // Frame i: joint i's frame at its reading, turned so that z is along its axis; then the flange.
  bool JointFrames(const double* q, const double* params,
                   std::vector<Pose>* T_base_joint) const override;
  bool AsSerialChain(const double* params, SerialChain* chain) const override;
  // The path from base_link to tip_link with the URDF's names, fixed joints, axes and limits, and
  // each movable joint's origin calibrated: Trans(x, y, z) R_parent_joint RPY(roll, pitch, yaw)
  // Rot(axis, offset).
  bool AsNamedChain(const double* params, NamedChain* chain) const override;
  // The `urdf` config with the URDF's absolute path and `params` as its `calibrated:` values.
  std::string CalibratedConfig(const ConfigNode& config, const double* params) const override;
  // Replaces the nominal value of the parameter called `name`; false when there is none.
  bool SetNominal(const std::string& name, double value);

  template <typename T>
  bool ForwardT(const double* q, const T* params, Transform<T>* T_base_flange) const {
    Transform<T> chain;
    for (size_t i = 0; i < chain_.joints.size(); ++i) {
      const T* p = params + kParamsPerJoint * i;
      chain = chain * JointOrigin(i, p);
      chain.R = chain.R * TurnAbout(chain_.joints[i].axis, T(q[i]) + p[kOffset]);
    }
    *T_base_flange = chain * chain_.T_last_joint_tip.cast<T>();
    return true;
  }

  // O_i: joint i's frame at q_i = -offset_i in the previous joint's (or the base's).
  template <typename T>
  Transform<T> JointOrigin(size_t joint, const T* p) const {
    const UrdfJoint& j = chain_.joints[joint];
    Transform<T> origin;
    origin.t = Vector3<T>(p[kX], p[kY], p[kZ]);
    origin.R = j.R_parent_joint.cast<T>() * RollPitchYaw(p[kRoll], p[kPitch], p[kYaw]);
    return j.T_previous_parent.cast<T>() * origin;
  }

  // Rodrigues' formula: a turn by `angle` about the unit `axis`.
  template <typename T>
  static Matrix3<T> TurnAbout(const Eigen::Vector3d& axis, const T& angle) {
    using std::cos;
    using std::sin;
    const T c = cos(angle), s = sin(angle);
    Matrix3<T> K;
    K << T(0), T(-axis.z()), T(axis.y()), T(axis.z()), T(0), T(-axis.x()), T(-axis.y()),
        T(axis.x()), T(0);
    return Matrix3<T>::Identity() * c + K * s + (axis * axis.transpose()).cast<T>() * (T(1) - c);
  }

  // Rz(yaw) Ry(pitch) Rx(roll), URDF's rpy.
  template <typename T>
  static Matrix3<T> RollPitchYaw(const T& roll, const T& pitch, const T& yaw) {
    using std::cos;
    using std::sin;
    const T cr = cos(roll), sr = sin(roll), cp = cos(pitch), sp = sin(pitch);
    const T cy = cos(yaw), sy = sin(yaw);
    Matrix3<T> R;
    R << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
        sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
        -sp, cp * sr, cp * cr;
    return R;
  }

 private:
  UrdfChain chain_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::urdf_robot
