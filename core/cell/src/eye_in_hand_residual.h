// The residual of a camera riding on a robot's flange (eye in hand), on Jets.
//
// The camera sees the world target, which defines the world, so the prediction is the world in
// the camera:
//
//   T_cam_world = T_flange_camera^-1 * T_base_flange(q)^-1 * T_world_base^-1
//
// compared with the measured pose as every residual is (TargetComparison: position in mm along
// the camera's x, y and depth, or rotation in rad about its axes, each divided by its sigma).
// Blocks: the robot's base (T_world_base), the camera's frame on the flange (T_flange_camera,
// the "<robot>.<camera>" tool block) and the robot model, each a frame block (frame_block.h)
// but the model. Wrapped by OnJets (jet_costs.h): Ceres's automatic differentiation gives the
// exact derivatives (a held block carries no derivative directions), which test_eye_in_hand
// checks against central differences with the model free.
#pragma once

#include <vector>

#include "workcell_residuals.h"

namespace cellmetry {

class EyeInHandResidual {
 public:
  EyeInHandResidual(const TargetComparison& comparison, const Eigen::Matrix3d& R_ref_world_base,
                    const Eigen::Matrix3d& R_ref_flange_camera, const RobotModel* model,
                    std::vector<double> q)
      : comparison_(comparison), R_world_base_(R_ref_world_base),
        R_flange_camera_(R_ref_flange_camera), model_(model), q_(std::move(q)) {}

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    const Transform<T> T_world_base = FrameFromBlock(blocks[0], R_world_base_);
    const Transform<T> T_flange_camera = FrameFromBlock(blocks[1], R_flange_camera_);
    Transform<T> T_base_flange;
    if (!model_->Forward(q_.data(), blocks[2], &T_base_flange)) return false;
    const Transform<T> T_cam_world = (T_world_base * T_base_flange * T_flange_camera).inverse();
    comparison_.Compare(T_cam_world, residual);
    return true;
  }

 private:
  TargetComparison comparison_;
  Eigen::Matrix3d R_world_base_, R_flange_camera_;
  const RobotModel* model_;
  std::vector<double> q_;
};

}  // namespace cellmetry
