// Residual functors of the workcell identification (internal to the core).
//
// Every residual compares a predicted target pose in a camera frame with the measured one:
//
//   T_cam_target = T_cam_world * T_world_base * T_base_flange(q) * T_flange_target
//
// either its position (mm, camera x/y/depth) or its rotation (rad, about the camera axes), each
// row divided by its sigma. When the robot model is held, chain_cost.h evaluates this with
// analytic derivatives (the hot path); ModelChainResidual below serves the case where robot model
// parameters are free and T_base_flange(q) must be differentiated too (Jets).
#pragma once

#include <ceres/ceres.h>

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
};

template <typename T>
Transform<T> CameraFromWorld(const T* world_cam_block, const Eigen::Matrix3d& R_ref) {
  return FrameFromBlock(world_cam_block, R_ref).inverse();
}

// Blocks (base, tool, [camera,] robot model). Evaluated with ceres::DynamicAutoDiffCostFunction.
class ModelChainResidual {
 public:
  ModelChainResidual(TargetComparison comparison, FrameRefs refs, const RobotModel* model,
                     std::vector<double> q, bool static_camera, Pose T_cam_world_measured)
      : comparison_(comparison), refs_(refs), model_(model), q_(std::move(q)),
        static_camera_(static_camera), T_cam_world_measured_(T_cam_world_measured) {}

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    const Transform<T> T_cam_world = static_camera_
                                         ? CameraFromWorld(blocks[2], refs_.world_cam)
                                         : T_cam_world_measured_.cast<T>();
    const T* model_params = blocks[static_camera_ ? 3 : 2];
    Transform<T> T_base_flange;
    if (!model_->Forward(q_.data(), model_params, &T_base_flange)) return false;
    const Transform<T> predicted = T_cam_world * FrameFromBlock(blocks[0], refs_.world_base) *
                                   T_base_flange * FrameFromBlock(blocks[1], refs_.flange_target);
    comparison_.Compare(predicted, residual);
    return true;
  }

 private:
  TargetComparison comparison_;
  FrameRefs refs_;
  const RobotModel* model_;
  std::vector<double> q_;
  bool static_camera_;
  Pose T_cam_world_measured_;
};

}  // namespace cellmetry
