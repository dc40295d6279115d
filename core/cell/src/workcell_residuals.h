// Residual functors of the workcell identification (internal to the core).
//
// Every residual compares a predicted target pose in a camera frame with the measured one:
//
//   T_cam_target = T_cam_world * T_world_base * T_base_flange(q) * T_flange_target
//
// either its position (mm, camera x/y/depth) or its rotation (rad, about the camera axes), each
// row divided by its sigma. When the robot model is held, chain_cost.h evaluates this with
// analytic derivatives (the hot path); where its parameters are free or effects act,
// effect_chain_cost.h does, with the model's flange twists.
#pragma once

#include <ceres/ceres.h>

#include <optional>

#include "cellmetry/basics/so3_jacobians.h"
#include "cellmetry/model/frame_block.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

enum class Compared { kPosition, kRotation };

// The measured pose and how to compare a prediction with it.
class TargetComparison {
 public:
  TargetComparison(Compared compared, const Pose& measured, const Eigen::Vector3d& sigma)
      : compared_(compared), measured_(measured), inv_sigma_(sigma.cwiseInverse()) {}

  Compared compared() const { return compared_; }
  const Pose& measured() const { return measured_; }
  const Eigen::Vector3d& inv_sigma() const { return inv_sigma_; }

  // A predicted position alone (compared() is kPosition).
  template <typename T>
  void ComparePosition(const Vector3<T>& predicted, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = (predicted[i] - T(measured_.t[i])) * T(inv_sigma_[i]);
  }

  template <typename T>
  void Compare(const Transform<T>& predicted, T* residual) const {
    Vector3<T> error;
    if (compared_ == Compared::kPosition) {
      error = predicted.t - measured_.t.cast<T>();
    } else {
      error = RotationError<T>(predicted.R, measured_.R.cast<T>());
    }
    for (int i = 0; i < 3; ++i) residual[i] = error[i] * T(inv_sigma_[i]);
  }

  // A position's residual is inv_sigma .* (predicted - measured): affine in the prediction
  // (SharedPredictionCost::AffineComparison). False for a rotation.
  bool Affine(Eigen::Vector3d* weight, Eigen::Vector3d* measured) const {
    if (compared_ != Compared::kPosition) return false;
    *weight = inv_sigma_;
    *measured = measured_.t;
    return true;
  }
  // The residual at `predicted` and, when not null, its derivative by the prediction's tangent
  // (shared_prediction_cost.h): the position's coordinates, or a left rotation of the prediction
  // Exp(d) R about the camera axes, whose rotation error moves by J_l^-1(error) d.
  void CompareLinearized(const Pose& predicted, double* residual,
                         Eigen::Matrix3d* d_residual) const {
    Eigen::Map<Eigen::Vector3d> r(residual);
    if (compared_ == Compared::kPosition) {
      r = (predicted.t - measured_.t).cwiseProduct(inv_sigma_);
      if (d_residual) *d_residual = inv_sigma_.asDiagonal();
      return;
    }
    if (d_residual == nullptr) {
      r = RotationError<double>(predicted.R, measured_.R).cwiseProduct(inv_sigma_);
      return;
    }
    Eigen::Vector3d error;
    Eigen::Matrix3d inverse_jacobian;
    RotationErrorAndInverseJacobian(predicted.R, measured_.R, &error, &inverse_jacobian);
    r = error.cwiseProduct(inv_sigma_);
    *d_residual = inv_sigma_.asDiagonal() * inverse_jacobian;
  }

 private:
  Compared compared_;
  Pose measured_;
  Eigen::Vector3d inv_sigma_;
};

// Starting rotations of the frame blocks a residual touches (see frame_block.h).
struct FrameRefs {
  Eigen::Matrix3d world_base = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d flange_target = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d world_cam = Eigen::Matrix3d::Identity();
  // A base or tool held entirely (a delta's base is the world; its marker is the config's):
  // their poses as plain numbers, and the Jet residuals leave their blocks out (a constant block
  // would still cost derivative passes).
  std::optional<Pose> held_world_base;
  std::optional<Pose> held_flange_target;
};

// Where each block is among a Jet residual's blocks: base, tool, camera, robot model in that
// order, those held or absent left out (-1).
struct JetChainLayout {
  int base = -1, tool = -1, camera = -1, model = -1;
  bool held_base_is_world = false;  // held at the identity (the world is the base)

  static JetChainLayout Of(const FrameRefs& refs, bool static_camera) {
    JetChainLayout layout;
    layout.held_base_is_world = refs.held_world_base &&
                                refs.held_world_base->R == Eigen::Matrix3d::Identity() &&
                                refs.held_world_base->t.isZero(0.0);
    int next = 0;
    layout.base = refs.held_world_base ? -1 : next++;
    layout.tool = refs.held_flange_target ? -1 : next++;
    layout.camera = static_camera ? next++ : -1;
    layout.model = next++;
    return layout;
  }

  template <typename T>
  Transform<T> Base(T const* const* blocks, const FrameRefs& refs) const {
    return base < 0 ? refs.held_world_base->cast<T>()
                    : FrameFromBlock(blocks[base], refs.world_base);
  }
  template <typename T>
  Transform<T> Tool(T const* const* blocks, const FrameRefs& refs) const {
    return tool < 0 ? refs.held_flange_target->cast<T>()
                    : FrameFromBlock(blocks[tool], refs.flange_target);
  }
  // `p` (base frame) in the world; a held base that is the world moves nothing.
  template <typename T>
  Vector3<T> WorldFromBase(T const* const* blocks, const FrameRefs& refs,
                           const Vector3<T>& p) const {
    if (base >= 0) return FrameBlockMap(blocks[base], refs.world_base, p);
    if (held_base_is_world) return p;
    return refs.held_world_base->cast<T>() * p;
  }
  // A world point in the base frame.
  template <typename T>
  Vector3<T> BaseFromWorld(T const* const* blocks, const FrameRefs& refs,
                           const Vector3<T>& p) const {
    if (base >= 0) return FrameBlockInverseMap(blocks[base], refs.world_base, p);
    if (held_base_is_world) return p;
    return refs.held_world_base->cast<T>().inverse() * p;
  }
  // The tool's origin on the flange.
  template <typename T>
  Vector3<T> ToolOrigin(T const* const* blocks, const FrameRefs& refs) const {
    if (tool < 0) return refs.held_flange_target->t.cast<T>();
    return Vector3<T>(blocks[tool][0], blocks[tool][1], blocks[tool][2]);
  }
};

template <typename T>
Transform<T> CameraFromWorld(const T* world_cam_block, const Eigen::Matrix3d& R_ref) {
  return FrameFromBlock(world_cam_block, R_ref).inverse();
}

}  // namespace cellmetry
