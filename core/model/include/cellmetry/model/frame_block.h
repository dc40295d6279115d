// FrameBlock: a rigid frame as six free-or-fixed parameters.
//
// A frame T_a_b is estimated as   R = exp([rx ry rz]) * R_ref,   t = [x y z],
// where R_ref is the frame's starting rotation (from a closed-form step). The parameters are a
// small rotation about frame a's axes and an absolute translation, so every solver sees a plain
// vector with no manifold, the rotation never nears the rotation vector's singularity, and the
// covariance of (rx, ry, rz) reads directly as rotation uncertainty about a's axes (rad).
// The 2020 paper fitted the nine entries of R freely and got non-orthonormal answers; this
// parametrisation cannot.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "cellmetry/basics/parameter.h"
#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/config_node.h"

namespace cellmetry {

inline const std::array<std::string, 6> kFrameParameterNames = {"x", "y", "z", "rx", "ry", "rz"};

struct FrameBlockSpec {
  Pose start = Pose::Identity();  // becomes R_ref and the starting translation
  std::array<bool, 6> free{};     // x y z rx ry rz
  std::string description;        // e.g. "UR3 base in the world"
};

// `free: [x, y, z, rx, ry, rz] | all | none` at `node`, or `fallback` without the key.
std::array<bool, 6> ReadFreeFlags(const ConfigNode& node, std::array<bool, 6> fallback);

// Parameters of a frame block (values relative to R_ref: rotation entries start at 0).
std::vector<Parameter> FrameParameters(const FrameBlockSpec& spec);

template <typename T>
Transform<T> FrameFromBlock(const T* block, const Eigen::Matrix3d& R_ref) {
  Transform<T> frame;
  frame.R = RotationFromRvec(block + 3) * R_ref.cast<T>();
  frame.t << block[0], block[1], block[2];
  return frame;
}

inline Pose FrameFromBlock(const double* block, const Eigen::Matrix3d& R_ref) {
  return FrameFromBlock<double>(block, R_ref);
}

// The two maps of a frame block applied to one point without forming R. On Jets this is about
// half the work of FrameFromBlock and a matrix product: exp() rotates the point directly
// (Rodrigues, ceres::AngleAxisRotatePoint) and R_ref stays plain numbers.
//
//   FrameBlockMap:        p_a = R p_b + t        = exp(w) (R_ref p_b) + t
//   FrameBlockInverseMap: p_b = R^T (p_a - t)    = R_ref^T exp(-w) (p_a - t)
template <typename T>
Vector3<T> FrameBlockMap(const T* block, const Eigen::Matrix3d& R_ref, const Vector3<T>& p_b) {
  Vector3<T> p_ref, p_a;
  for (int i = 0; i < 3; ++i) {
    p_ref[i] = R_ref(i, 0) * p_b[0] + R_ref(i, 1) * p_b[1] + R_ref(i, 2) * p_b[2];
  }
  ceres::AngleAxisRotatePoint(block + 3, p_ref.data(), p_a.data());
  for (int i = 0; i < 3; ++i) p_a[i] += block[i];
  return p_a;
}

// A point given as plain numbers (a measurement): R_ref p_b needs no derivatives.
template <typename T>
Vector3<T> FrameBlockMapFixedPoint(const T* block, const Eigen::Matrix3d& R_ref,
                                   const Eigen::Vector3d& p_b) {
  const Eigen::Vector3d p_ref = R_ref * p_b;
  const T p_ref_t[3] = {T(p_ref[0]), T(p_ref[1]), T(p_ref[2])};
  Vector3<T> p_a;
  ceres::AngleAxisRotatePoint(block + 3, p_ref_t, p_a.data());
  for (int i = 0; i < 3; ++i) p_a[i] += block[i];
  return p_a;
}

template <typename T>
Vector3<T> FrameBlockInverseMap(const T* block, const Eigen::Matrix3d& R_ref,
                                const Vector3<T>& p_a) {
  const T minus_w[3] = {-block[3], -block[4], -block[5]};
  Vector3<T> shifted, turned, p_b;
  for (int i = 0; i < 3; ++i) shifted[i] = p_a[i] - block[i];
  ceres::AngleAxisRotatePoint(minus_w, shifted.data(), turned.data());
  for (int i = 0; i < 3; ++i) {
    p_b[i] = R_ref(0, i) * turned[0] + R_ref(1, i) * turned[1] + R_ref(2, i) * turned[2];
  }
  return p_b;
}

}  // namespace cellmetry
