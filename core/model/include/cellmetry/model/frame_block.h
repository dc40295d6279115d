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
  Pose start = Pose::Identity();          // becomes R_ref and the starting translation
  std::array<bool, 6> free{};             // x y z rx ry rz
  std::string description;                // e.g. "UR3 base in the world"
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

}  // namespace cellmetry
