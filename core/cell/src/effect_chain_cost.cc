// EffectChainCost (effect_chain_cost.h): the chain in plain numbers, Jets on each effect stage
// alone, closed-form motions of the prediction for frames and model.
#include "effect_chain_cost.h"

#include <stdexcept>

#include "cellmetry/basics/so3_jacobians.h"
#include "cellmetry/model/effect_chain.h"
#include "frame_cache.h"

namespace cellmetry {
namespace {

using Motion = Eigen::Matrix<double, 6, 6>;  // d(s, w) / d(frame block), s then w

// (s; w) of a frame block's translation and turn: s = [t_part, rotation_shift], w = turn.
Motion FrameMotion(const Eigen::Matrix3d& d_shift_d_t, const Eigen::Matrix3d& d_shift_d_r,
                   const Eigen::Matrix3d& d_turn_d_r) {
  Motion D = Motion::Zero();
  D.topLeftCorner<3, 3>() = d_shift_d_t;
  D.topRightCorner<3, 3>() = d_shift_d_r;
  D.bottomRightCorner<3, 3>() = d_turn_d_r;
  return D;
}

// Writes a 3 x cols Jacobian row-major where Ceres asked for it.
void Store(double* jacobian, const Eigen::Matrix<double, 3, Eigen::Dynamic>& J) {
  if (jacobian == nullptr) return;
  Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>>(jacobian, 3, J.cols()) = J;
}

}  // namespace

struct EffectChainCost::Chain {
  Pose P;  // the target in the camera, before the measurement effects
  Pose T_world_base, T_base_flange, T_flange_target, T_world_cam;
  Eigen::Vector3d p_world;                          // the target's origin in the world
  Eigen::Matrix<double, 6, Eigen::Dynamic> twists;  // the model's flange twists (base frame)
  Eigen::Matrix3d J_base, J_tool, J_camera;         // each frame block's left Jacobian (when asked)
  const double* base = nullptr;
  const double* tool = nullptr;
  const double* camera = nullptr;
  FlangeTwists effect_twists;  // the flange's (s; w) per effect parameter (joint, flange stage)
};

// What a flange twist (dt, w) in the base frame does to the prediction P: it moves the target by
// dt + w x (R_bf t_tool) and turns it by w, both seen in the camera.
Eigen::Matrix<double, 6, 6> EffectChainCost::FlangeToCamera(const Chain& c) {
  const Eigen::Matrix3d R_cb = c.T_world_cam.R.transpose() * c.T_world_base.R;
  const Eigen::Vector3d lever = c.T_base_flange.R * c.T_flange_target.t;
  Motion to_camera = Motion::Zero();
  to_camera.topLeftCorner<3, 3>() = R_cb;
  to_camera.topRightCorner<3, 3>() = -R_cb * Skew(lever);
  to_camera.bottomRightCorner<3, 3>() = R_cb;
  return to_camera;
}

ChainEffectList::ChainEffectList(std::vector<const Effect*> effects_in, std::vector<int> sizes_in)
    : effects(std::move(effects_in)), sizes(std::move(sizes_in)) {
  for (int size : sizes) num_params += size;
}

EffectChainCost::EffectChainCost(TargetComparison comparison, std::shared_ptr<const FrameRefs> refs,
                                 const RobotModel* model, EffectContext context, bool static_camera,
                                 const Pose& T_cam_world_measured,
                                 std::shared_ptr<const ChainEffectList> effects,
                                 std::shared_ptr<ForwardMemo> forward,
                                 const EffectChainCost* same_as)
    : comparison_(comparison), refs_(std::move(refs)), model_(model), context_(std::move(context)),
      static_camera_(static_camera), T_world_cam_fixed_(T_cam_world_measured.inverse()),
      list_(std::move(effects)), effects_(list_->effects), effect_sizes_(list_->sizes),
      forward_(std::move(forward)), key_(same_as ? same_as->key_ : this) {
  if (same_as && same_as->comparison_.compared() != comparison_.compared()) {
    throw std::logic_error("EffectChainCost: a position and a rotation cannot share a prediction");
  }
  // Frames and model, then the effects (one allocation per cost).
  const int num_frames = (model_ ? 2 : 0) + (static_camera_ ? 1 : 0);
  first_effect_ = num_frames + (model_ ? 1 : 0);
  auto* sizes = mutable_parameter_block_sizes();
  sizes->reserve(static_cast<size_t>(first_effect_) + effect_sizes_.size());
  sizes->assign(static_cast<size_t>(num_frames), 6);
  if (model_) sizes->push_back(static_cast<int>(model_->parameters().size()));
  sizes->insert(sizes->end(), effect_sizes_.begin(), effect_sizes_.end());
  num_effect_params_ = list_->num_params;
  joint_effects_ = model_ && AnyEffectAt(effects_, EffectStage::kJoint);
  flange_effects_ = model_ && AnyEffectAt(effects_, EffectStage::kFlange);
}

EffectChainCost::EffectChainCost(TargetComparison comparison, FrameRefs refs,
                                 const RobotModel* model, EffectContext context, bool static_camera,
                                 const Pose& T_cam_world_measured,
                                 std::vector<const Effect*> effects,
                                 const std::vector<int>& effect_sizes)
    : EffectChainCost(comparison, std::make_shared<const FrameRefs>(std::move(refs)), model,
                      std::move(context), static_camera, T_cam_world_measured,
                      std::make_shared<const ChainEffectList>(std::move(effects), effect_sizes)) {}

bool EffectChainCost::FlangeOfModel(const double* model_params, double const* const* effect_params,
                                    bool with_twists, bool effect_twists, Chain* c) const {
  // The joint stage: dq through the model's joint offsets (effect_chain.h, FlangeWithEffects).
  thread_local std::vector<double> dq, shifted;
  thread_local Eigen::MatrixXd d_dq;
  const double* at = model_params;
  if (joint_effects_) {
    LinearizeJointStage(effects_, effect_sizes_, effect_params, context_, &dq,
                        effect_twists ? &d_dq : nullptr);
    shifted.assign(model_params, model_params + model_->parameters().size());
    for (int j = 0; j < model_->num_joints(); ++j) {
      const int offset = model_->JointOffsetParameter(j);
      if (offset >= 0) shifted[offset] += dq[j];
    }
    at = shifted.data();
  }
  const bool twists = with_twists || (effect_twists && joint_effects_);
  Eigen::Matrix<double, 6, Eigen::Dynamic>* twists_out = twists ? &c->twists : nullptr;
  bool ok;
  if (forward_) {
    ok = forward_->Forward(at, &c->T_base_flange, twists_out);
  } else {
    ok = twists ? model_->ForwardWithTwists(context_.q, at, &c->T_base_flange, twists_out)
                : model_->Forward(context_.q, at, &c->T_base_flange);
  }
  if (!ok) return false;
  if (effect_twists) {
    c->effect_twists.setZero(6, num_effect_params_);
    for (int j = 0; joint_effects_ && j < model_->num_joints(); ++j) {
      const int offset = model_->JointOffsetParameter(j);
      if (offset >= 0) c->effect_twists += c->twists.col(offset) * d_dq.row(j);
    }
  }
  if (flange_effects_) {  // the flange stage, and what it makes of the motions before it
    if (!twists && !effect_twists) {
      LinearizeFlangeStage(effects_, effect_sizes_, effect_params, context_, &c->T_base_flange,
                           nullptr, nullptr);
      return true;
    }
    Eigen::Matrix<double, 6, 6> motion_map;
    FlangeTwists flange_twists;
    LinearizeFlangeStage(effects_, effect_sizes_, effect_params, context_, &c->T_base_flange,
                         &motion_map, &flange_twists);
    if (twists) c->twists = motion_map * c->twists;
    if (effect_twists) c->effect_twists = motion_map * c->effect_twists + flange_twists;
  }
  return true;
}

bool EffectChainCost::PredictChain(double const* const* parameters, bool with_twists,
                                   bool with_jacobians, bool effect_twists, Chain* c) const {
  int k = 0;
  c->base = model_ ? parameters[k++] : nullptr;
  c->tool = model_ ? parameters[k++] : nullptr;
  c->camera = static_camera_ ? parameters[k++] : nullptr;
  if (model_) {
    const double* model_params = parameters[k++];
    if (!FlangeOfModel(model_params, parameters + first_effect_, with_twists,
                       effect_twists && (joint_effects_ || flange_effects_), c)) {
      return false;
    }
    // The frames every block shares, made once per thread for these values (frame_cache.h).
    const CachedFrame base = FrameOfBlock(c->base, refs_->world_base, with_jacobians);
    const CachedFrame tool = FrameOfBlock(c->tool, refs_->flange_target, with_jacobians);
    c->T_world_base = base.T;
    c->T_flange_target = tool.T;
    c->J_base = base.J_left;
    c->J_tool = tool.J_left;
  } else {  // the world target: the world frame itself
    c->T_world_base = c->T_base_flange = c->T_flange_target = Pose::Identity();
  }
  if (c->camera) {
    const CachedFrame camera = FrameOfBlock(c->camera, refs_->world_cam, with_jacobians);
    c->T_world_cam = camera.T;
    c->J_camera = camera.J_left;
  } else {
    c->T_world_cam = T_world_cam_fixed_;
  }
  const Eigen::Matrix3d R_cw = c->T_world_cam.R.transpose();
  const Pose T_world_flange = c->T_world_base * c->T_base_flange;
  c->p_world = T_world_flange * c->T_flange_target.t;
  c->P.t = R_cw * (c->p_world - c->T_world_cam.t);
  c->P.R = R_cw * T_world_flange.R * c->T_flange_target.R;
  return true;
}

void EffectChainCost::LastStage(const Transform<Jet>& moved, Output output, const Pose& measured,
                                Jet* out) const {
  if (output == Output::kResidual) {
    comparison_.Compare(moved, out);
  } else if (comparison_.compared() == Compared::kPosition) {
    for (int i = 0; i < 3; ++i) out[i] = moved.t[i];
  } else {  // moved.R = Exp(d) measured.R to first order: [d]x = moved.R measured.R^T - I
    Matrix3<Jet> turn = moved.R * measured.R.transpose().cast<Jet>();
    out[0] = 0.5 * (turn(2, 1) - turn(1, 2));
    out[1] = 0.5 * (turn(0, 2) - turn(2, 0));
    out[2] = 0.5 * (turn(1, 0) - turn(0, 1));
  }
}

void EffectChainCost::MeasureAndCompare(const Pose& P, double const* const* effect_params,
                                        bool effects_asked, Output output, double* values,
                                        Pose* measured,
                                        Eigen::Matrix<double, 3, Eigen::Dynamic>* H) const {
  // Directions: s (3), w (3), then the measurement effects' parameters where asked for.
  thread_local EffectParameterJets effect_jets;  // an evaluation allocates nothing after the first
  effect_jets.Reset(effects_, effect_sizes_, effect_params, EffectStage::kMeasurement, 6);
  const int directions = effects_asked ? effect_jets.end_direction() : 6;
  thread_local Eigen::Matrix<double, 3, Eigen::Dynamic> by_direction;
  by_direction.resize(3, directions);
  Pose at;  // the measured pose (the Jets' values), what the tangent is taken about
  for (int first = 0; first < directions; first += kJetStride) {
    effect_jets.Seed(first);
    Transform<Jet> moved = FirstOrderMotion(P, first);
    ApplyMeasurement(effects_, effect_jets.pointers(), context_, &moved);
    if (first == 0) {
      for (int i = 0; i < 3; ++i) {
        at.t[i] = moved.t[i].a;
        for (int j = 0; j < 3; ++j) at.R(i, j) = moved.R(i, j).a;
      }
    }
    Jet r[3];
    LastStage(moved, output, at, r);
    for (int i = 0; i < 3; ++i) {
      values[i] = r[i].a;
      for (int d = 0; d < kJetStride && first + d < directions; ++d) {
        by_direction(i, first + d) = r[i].v[d];
      }
    }
  }
  if (measured) *measured = at;
  // H: the motion's six columns, then one per effect parameter (zero for the other stages').
  H->setZero(3, 6 + (effects_asked ? num_effect_params_ : 0));
  H->leftCols<6>() = by_direction.leftCols<6>();
  if (effects_asked) effect_jets.ByParameter(by_direction, H->rightCols(num_effect_params_));
}

void EffectChainCost::StoreFrameJacobians(const Chain& c,
                                          const Eigen::Matrix<double, 3, 6>& H_motion,
                                          double** jacobians) const {
  const Eigen::Matrix3d R_cw = c.T_world_cam.R.transpose();
  const Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  int k = 0;
  if (model_) {
    if (jacobians[k]) {  // base: p_world - t turns with it
      const Eigen::Matrix3d& J_l = c.J_base;
      Store(jacobians[k],
            H_motion *
                FrameMotion(R_cw, -R_cw * Skew(c.p_world - c.T_world_base.t) * J_l, R_cw * J_l));
    }
    ++k;
    if (jacobians[k]) {  // tool: shifts along the flange's axes, turns about them
      const Eigen::Matrix3d R_cf = R_cw * c.T_world_base.R * c.T_base_flange.R;
      Store(jacobians[k], H_motion * FrameMotion(R_cf, zero, R_cf * c.J_tool));
    }
    ++k;
  }
  if (static_camera_) {
    if (jacobians[k]) {  // camera: the world moves the other way
      const Eigen::Matrix3d& J_l = c.J_camera;
      Store(jacobians[k],
            H_motion *
                FrameMotion(-R_cw, R_cw * Skew(c.p_world - c.T_world_cam.t) * J_l, -R_cw * J_l));
    }
    ++k;
  }
  if (model_ && jacobians[k]) Store(jacobians[k], H_motion * (FlangeToCamera(c) * c.twists));
}

bool EffectChainCost::Evaluate(double const* const* parameters, double* residuals,
                               double** jacobians) const {
  return Linearize(parameters, Output::kResidual, residuals, nullptr, jacobians);
}

bool EffectChainCost::Predict(double const* const* parameters, Pose* prediction,
                              double** tangent_jacobians) const {
  double tangent[3];
  return Linearize(parameters, Output::kTangent, tangent, prediction, tangent_jacobians);
}

void EffectChainCost::Compare(const Pose& prediction, double* residual,
                              Eigen::Matrix3d* d_residual) const {
  comparison_.CompareLinearized(prediction, residual, d_residual);
}

bool EffectChainCost::Linearize(double const* const* parameters, Output output, double* values,
                                Pose* measured, double** jacobians) const {
  const int model_slot = first_effect_ - 1;
  const bool model_asked = model_ && jacobians && jacobians[model_slot];
  bool effects_asked = false;
  for (size_t e = 0; jacobians && e < effects_.size(); ++e) {
    effects_asked = effects_asked || jacobians[first_effect_ + e] != nullptr;
  }
  thread_local Chain c;  // its twists' storage is reused
  if (!PredictChain(parameters, model_asked, jacobians != nullptr, effects_asked, &c)) {
    return false;
  }
  double const* const* effect_params = parameters + first_effect_;
  if (jacobians == nullptr) {
    Transform<double> moved = c.P;
    ApplyMeasurement(effects_, effect_params, context_, &moved);
    if (output == Output::kResidual) comparison_.Compare(moved, values);
    if (measured) *measured = moved;
    return true;
  }
  thread_local Eigen::Matrix<double, 3, Eigen::Dynamic> H;
  MeasureAndCompare(c.P, effect_params, effects_asked, output, values, measured, &H);
  StoreFrameJacobians(c, H.leftCols<6>(), jacobians);
  if (!effects_asked) return true;
  // The joint and flange effects act through the flange's motion; the measurement effects
  // directly (their columns of H; the others' are zero there).
  if (model_ && (joint_effects_ || flange_effects_)) {
    H.rightCols(num_effect_params_) += H.leftCols<6>() * (FlangeToCamera(c) * c.effect_twists);
  }
  int column = 6;
  for (size_t e = 0; e < effects_.size(); ++e) {
    Store(jacobians[first_effect_ + e], H.middleCols(column, effect_sizes_[e]));
    column += effect_sizes_[e];
  }
  return true;
}

}  // namespace cellmetry
