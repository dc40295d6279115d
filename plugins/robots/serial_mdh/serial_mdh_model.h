// SerialMdhModel: a serial arm in modified Denavit-Hartenberg notation (Craig 2005, sec. 3.4).
//
// Link i (1-based) maps frame i into frame i-1:
//
//   A_i = Rx(alpha_i) Tx(a_i) Ry(beta_i) Rz(q_i + offset_i) Tz(d_i)
//
// where alpha_i, a_i are Craig's alpha_{i-1}, a_{i-1} (the 2020 paper's Table 1 lists them on
// joint i's row, as here). beta_i is Hayati's extra angle (Hayati & Mirmirani 1985): 0 and held
// by default; free it instead of d_i where axes i-1 and i are parallel, because there MDH is
// ill-conditioned (a small tilt of a parallel axis moves the common normal far away).
//
// T_base_flange = A_1 ... A_n. Parameters, per joint i: "j<i>.alpha" (rad), "j<i>.a" (mm),
// "j<i>.beta" (rad), "j<i>.d" (mm), "j<i>.offset" (rad).
//
// As a chain of revolute joints (serial_chain.h), for exports: Rz(q + offset) Tz(d) =
// Rz(offset) Tz(d) Rz(q), since turns and shifts along one axis commute, so joint i's origin at
// q_i = 0 is A_i(q_i = 0) = Rx(alpha_i) Tx(a_i) Ry(beta_i) Rz(offset_i) Tz(d_i), and the flange
// is the last joint's frame. Every parameter of this model is rigid geometry: the chain holds
// all of it.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/model/robot_model.h"

namespace cellmetry::serial_mdh {

inline constexpr int kParamsPerJoint = 5;  // alpha, a, beta, d, offset
enum Entry { kAlpha = 0, kA = 1, kBeta = 2, kD = 3, kOffset = 4 };

struct Joint {
  double alpha = 0.0;
  double a = 0.0;
  double beta = 0.0;
  double d = 0.0;
  double offset = 0.0;
};

class SerialMdhModel : public RobotModelFromTemplate<SerialMdhModel> {
 public:
  explicit SerialMdhModel(std::vector<Joint> joints);

  int num_joints() const override { return static_cast<int>(joints_.size()); }
  const std::vector<Parameter>& parameters() const override { return parameters_; }
  std::vector<std::string> Warnings(const std::vector<Parameter>& job_parameters) const override;
  bool AsSerialChain(const double* params, SerialChain* chain) const override;
  // The `serial_mdh` config with `params` as its table (mm, rad), name and description kept.
  std::string CalibratedConfig(const ConfigNode& config, const double* params) const override;
  int JointOffsetParameter(int joint) const override { return kParamsPerJoint * joint + kOffset; }
  // Closed form: each parameter turns the rest of the chain about one axis (alpha, beta,
  // offset) or shifts it along one (a, d); no Jets.
  bool ForwardWithTwists(const double* q, const double* params, Pose* T_base_flange,
                         Eigen::Matrix<double, 6, Eigen::Dynamic>* twists) const override;
  // Frame i of the chain (A_1 ... A_i) has joint i's axis as its z axis; the flange is frame n.
  bool JointFrames(const double* q, const double* params,
                   std::vector<Pose>* T_base_joint) const override {
    T_base_joint->clear();
    Pose chain = Pose::Identity();
    for (size_t i = 0; i < joints_.size(); ++i) {
      const double* p = params + kParamsPerJoint * i;
      chain = chain * Link(p[kAlpha], p[kA], p[kBeta], q[i] + p[kOffset], p[kD]);
      T_base_joint->push_back(chain);
    }
    T_base_joint->push_back(chain);
    return true;
  }

  template <typename T>
  bool ForwardT(const double* q, const T* params, Transform<T>* T_base_flange) const {
    using std::cos;
    using std::sin;
    Transform<T> chain;
    for (size_t i = 0; i < joints_.size(); ++i) {
      const T* p = params + kParamsPerJoint * i;
      chain = chain * Link(p[kAlpha], p[kA], p[kBeta], T(q[i]) + p[kOffset], p[kD]);
    }
    *T_base_flange = chain;
    return true;
  }

  // A = Rx(alpha) Tx(a) Ry(beta) Rz(theta) Tz(d), written out.
  template <typename T>
  static Transform<T> Link(const T& alpha, const T& a, const T& beta, const T& theta, const T& d) {
    using std::cos;
    using std::sin;
    const T ca = cos(alpha), sa = sin(alpha), cb = cos(beta), sb = sin(beta);
    const T ct = cos(theta), st = sin(theta);
    Matrix3<T> Rx, Ry, Rz;
    Rx << T(1), T(0), T(0), T(0), ca, -sa, T(0), sa, ca;
    Ry << cb, T(0), sb, T(0), T(1), T(0), -sb, T(0), cb;
    Rz << ct, -st, T(0), st, ct, T(0), T(0), T(0), T(1);
    Transform<T> link;
    const Matrix3<T> R_xy = Rx * Ry;
    link.R = R_xy * Rz;
    link.t = Vector3<T>(a, T(0), T(0)) + link.R.col(2) * d;
    return link;
  }

 private:
  std::vector<Joint> joints_;
  std::vector<Parameter> parameters_;
};

}  // namespace cellmetry::serial_mdh
