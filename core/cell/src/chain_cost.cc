// ChainCost (chain_cost.h): the chain predicted in closed form, then compared.
#include "chain_cost.h"

#include <stdexcept>

#include "cellmetry/basics/so3_jacobians.h"
#include "frame_cache.h"

namespace cellmetry {
namespace {

using TangentJacobian = Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>>;

// Writes [dt | dr] of the tangent if it was asked for this block.
void Store(double* jacobian, const Eigen::Matrix3d& d_translation,
           const Eigen::Matrix3d& d_rotation) {
  if (jacobian == nullptr) return;
  TangentJacobian J(jacobian);
  J.leftCols<3>() = d_translation;
  J.rightCols<3>() = d_rotation;
}

}  // namespace

ChainCost::ChainCost(TargetComparison comparison, std::shared_ptr<const FrameRefs> refs,
                     ChainBlocks blocks, const Pose& T_base_flange, const Pose& T_cam_world_fixed,
                     const ChainCost* same_as)
    : comparison_(comparison), blocks_(blocks), T_base_flange_(T_base_flange),
      refs_(std::move(refs)), key_(same_as ? same_as->key_ : this) {
  if (same_as && same_as->comparison_.compared() != comparison_.compared()) {
    throw std::logic_error("ChainCost: a position and a rotation cannot share a prediction");
  }
  if (!blocks.camera) {
    T_world_cam_fixed_ = std::make_unique<const Pose>(T_cam_world_fixed.inverse());
  }
  // Every frame block is 6 wide (one allocation: 22,500 of these make exp_a's problem).
  const int num_frames = int{blocks.base} + int{blocks.tool} + int{blocks.camera};
  mutable_parameter_block_sizes()->assign(num_frames, 6);
}

ChainCost::ChainCost(TargetComparison comparison, FrameRefs refs, ChainBlocks blocks,
                     const Pose& T_base_flange, const Pose& T_cam_world_fixed)
    : ChainCost(comparison, std::make_shared<const FrameRefs>(std::move(refs)), blocks,
                T_base_flange, T_cam_world_fixed) {}

struct ChainCost::State {
  CachedFrame base, tool, camera;  // of the blocks that are parameters
  Pose T_world_base, T_flange_target, T_world_cam, T_world_flange;
  Eigen::Matrix3d R_cw;
  Eigen::Vector3d p_world;  // the target's origin
};

void ChainCost::MakeState(double const* const* parameters, bool with_jacobian, State* state) const {
  int k = 0;
  // The frames every residual shares, each made once per thread for these values (frame_cache.h).
  if (blocks_.base) state->base = FrameOfBlock(parameters[k++], refs_->world_base, with_jacobian);
  if (blocks_.tool) {
    state->tool = FrameOfBlock(parameters[k++], refs_->flange_target, with_jacobian);
  }
  if (blocks_.camera) {
    state->camera = FrameOfBlock(parameters[k++], refs_->world_cam, with_jacobian);
  }
  state->T_world_base = blocks_.base ? state->base.T : Pose::Identity();
  state->T_flange_target = blocks_.tool ? state->tool.T : Pose::Identity();
  state->T_world_cam = blocks_.camera ? state->camera.T : *T_world_cam_fixed_;
  state->R_cw = state->T_world_cam.R.transpose();
  state->T_world_flange = state->T_world_base * T_base_flange_;
  state->p_world = state->T_world_flange * state->T_flange_target.t;
}

void ChainCost::PredictionOf(const State& c, Pose* prediction) const {
  if (comparison_.compared() == Compared::kPosition) {
    prediction->t = c.R_cw * (c.p_world - c.T_world_cam.t);
  } else {
    prediction->R = c.R_cw * c.T_world_flange.R * c.T_flange_target.R;
  }
}

void ChainCost::StoreJacobians(const State& c, const Eigen::Matrix3d& L, double** jacobians) const {
  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  const Eigen::Matrix3d L_R_cw = L * c.R_cw;
  int k = 0;
  if (comparison_.compared() == Compared::kPosition) {
    if (blocks_.base) {
      Store(jacobians[k++], L_R_cw, -L_R_cw * Skew(c.p_world - c.T_world_base.t) * c.base.J_left);
    }
    if (blocks_.tool) Store(jacobians[k++], L_R_cw * c.T_world_flange.R, zero);
    if (blocks_.camera) {
      Store(jacobians[k++], -L_R_cw, L_R_cw * Skew(c.p_world - c.T_world_cam.t) * c.camera.J_left);
    }
    return;
  }
  // A left perturbation Exp(d) of a factor rotates the prediction by Exp(R d) in the camera
  // frame, with R the rotation from that factor's left frame to the camera.
  if (blocks_.base) Store(jacobians[k++], zero, L_R_cw * c.base.J_left);
  if (blocks_.tool) Store(jacobians[k++], zero, L_R_cw * c.T_world_flange.R * c.tool.J_left);
  if (blocks_.camera) Store(jacobians[k++], zero, -L_R_cw * c.camera.J_left);
}

bool ChainCost::Predict(double const* const* parameters, Pose* prediction,
                        double** tangent_jacobians) const {
  State c;
  MakeState(parameters, tangent_jacobians != nullptr, &c);
  PredictionOf(c, prediction);
  if (tangent_jacobians) StoreJacobians(c, Eigen::Matrix3d::Identity(), tangent_jacobians);
  return true;
}

void ChainCost::Compare(const Pose& prediction, double* residual,
                        Eigen::Matrix3d* d_residual) const {
  comparison_.CompareLinearized(prediction, residual, d_residual);
}

bool ChainCost::Evaluate(double const* const* parameters, double* residuals,
                         double** jacobians) const {
  State c;
  MakeState(parameters, jacobians != nullptr, &c);
  Pose prediction;
  PredictionOf(c, &prediction);
  Eigen::Matrix3d D;
  ChainCost::Compare(prediction, residuals, jacobians ? &D : nullptr);
  if (jacobians) StoreJacobians(c, D, jacobians);
  return true;
}

}  // namespace cellmetry
