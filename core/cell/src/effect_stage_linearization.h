// The joint and flange stages of the effect chain (effect_chain.h), linearized for
// EffectChainCost (internal to the cell layer).
//
// EffectChainCost differentiates the chain in closed form through small motions of the flange
// and of the prediction in the camera. What the joint and flange effects add to that:
//
//   joint stage   dq (rad) and d dq / d(effect parameters). dq enters the model through its
//                 joint offset parameters (RobotModel::JointOffsetParameter), so the model's
//                 flange twists for those offsets carry it on to the flange.
//   flange stage  the flange after the effects, and how the flange's motion after them (a shift
//                 s and a turn w in the base frame: p + s, Exp(w) R) follows the motion before
//                 them and each effect parameter.
//
// Both come from Jets over the stage alone (its effects' parameters; for the flange also the six
// motion directions): a few dozen operations per pass, where Jets over the whole chain ran the
// forward kinematics once per kJetStride parameters. Effect parameters are numbered in effect
// order, every effect's (a stage's columns are zero for the other stages' effects).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "cellmetry/model/effect.h"
#include "cellmetry/model/robot_model.h"

namespace cellmetry {

// Twists (s; w) of the flange, base frame, one column per direction.
using FlangeTwists = Eigen::Matrix<double, 6, Eigen::Dynamic>;

// The joint stage: `dq` (context.num_joints values) and, with `d_dq` not null, its Jacobian with
// respect to every effect parameter (num_joints x total).
void LinearizeJointStage(const std::vector<const Effect*>& effects,
                         const std::vector<int>& effect_sizes, double const* const* effect_params,
                         const EffectContext& context, std::vector<double>* dq,
                         Eigen::MatrixXd* d_dq);

// The flange stage on `T_base_flange` (replaced by the flange after the effects). With
// `motion_map` and `effect_twists` not null: the output's (s; w) per input (s; w) (6 x 6) and per
// effect parameter (6 x total). A flange effect must keep the rotation a rotation (effect.h):
// the turn is read from the rotation's change as dR R^T.
void LinearizeFlangeStage(const std::vector<const Effect*>& effects,
                          const std::vector<int>& effect_sizes, double const* const* effect_params,
                          const EffectContext& context, Pose* T_base_flange,
                          Eigen::Matrix<double, 6, 6>* motion_map, FlangeTwists* effect_twists);

// Every effect parameter as a Jet, for a pass over one stage: only the parameters of the effects
// at that stage carry directions (numbered from `first_direction` in effect order), the others
// are constants. Reused per thread by the flange and measurement stages' linearizations.
class EffectParameterJets {
 public:
  void Reset(const std::vector<const Effect*>& effects, const std::vector<int>& effect_sizes,
             double const* const* effect_params, EffectStage stage, int first_direction);
  // Seeds the pass beginning at direction `first` (kJetStride directions).
  void Seed(int first);
  // One past the last direction given to a parameter.
  int end_direction() const { return end_direction_; }
  int count() const { return static_cast<int>(jets_.size()); }
  Jet const* const* pointers() const { return pointers_.data(); }
  // Copies `by_direction`'s columns to `by_parameter`, one column per effect parameter in effect
  // order (count() of them); a parameter without a direction keeps the column it had.
  void ByParameter(const Eigen::Ref<const Eigen::MatrixXd>& by_direction,
                   Eigen::Ref<Eigen::MatrixXd> by_parameter) const;

 private:
  std::vector<Jet> jets_;
  std::vector<const Jet*> pointers_;
  std::vector<int> direction_of_;
  int end_direction_ = 0;
};

// `P` moved by a shift s and a turn w (P.t + s, Exp(w) P.R) to first order, which is all a Jet
// carries (Exp(w) = I + [w]x): s and w are directions 0-5, seeded where they fall in the pass
// beginning at direction `first`. The flange and measurement stages' Jets start from it.
Transform<Jet> FirstOrderMotion(const Pose& P, int first);

// Whether any effect acts at `stage`.
bool AnyEffectAt(const std::vector<const Effect*>& effects, EffectStage stage);

}  // namespace cellmetry
