// The joint and flange stages linearized on Jets over the stage alone
// (effect_stage_linearization.h).
#include "effect_stage_linearization.h"

#include "cellmetry/model/effect_chain.h"

namespace cellmetry {
namespace {

// Direction d of a pass beginning at `first` as a Jet's unit, or nothing outside the pass.
void SeedUnit(int direction, int first, Jet* jet) {
  if (direction >= first && direction < first + kJetStride) jet->v[direction - first] = 1.0;
}

// The turn w of a rotation's change dR at R: [w]x = dR R^T (skew for a rotation's change; its
// antisymmetric part is taken).
Eigen::Vector3d TurnOf(const Eigen::Matrix3d& dR, const Eigen::Matrix3d& R) {
  const Eigen::Matrix3d A = dR * R.transpose();
  return 0.5 * Eigen::Vector3d(A(2, 1) - A(1, 2), A(0, 2) - A(2, 0), A(1, 0) - A(0, 1));
}

}  // namespace

void EffectParameterJets::Reset(const std::vector<const Effect*>& effects,
                                const std::vector<int>& effect_sizes,
                                double const* const* effect_params, EffectStage stage,
                                int first_direction) {
  jets_.clear();
  pointers_.clear();
  direction_of_.clear();
  end_direction_ = first_direction;
  for (size_t e = 0; e < effects.size(); ++e) {
    const bool at_stage = effects[e]->stage() == stage;
    for (int i = 0; i < effect_sizes[e]; ++i) {
      jets_.emplace_back(effect_params[e][i]);
      direction_of_.push_back(at_stage ? end_direction_++ : -1);
    }
  }
  for (size_t e = 0, at = 0; e < effects.size(); at += effect_sizes[e++]) {
    pointers_.push_back(jets_.data() + at);
  }
}

void EffectParameterJets::Seed(int first) {
  for (int i = 0; i < count(); ++i) {
    jets_[i].v.setZero();
    if (direction_of_[i] >= 0) SeedUnit(direction_of_[i], first, &jets_[i]);
  }
}

void EffectParameterJets::ByParameter(const Eigen::Ref<const Eigen::MatrixXd>& by_direction,
                                      Eigen::Ref<Eigen::MatrixXd> by_parameter) const {
  for (int i = 0; i < count(); ++i) {
    if (direction_of_[i] >= 0) by_parameter.col(i) = by_direction.col(direction_of_[i]);
  }
}

Transform<Jet> FirstOrderMotion(const Pose& P, int first) {
  Jet s[3], w[3];
  for (int i = 0; i < 3; ++i) {
    s[i] = Jet(0.0);
    w[i] = Jet(0.0);
    SeedUnit(i, first, &s[i]);
    SeedUnit(i + 3, first, &w[i]);
  }
  Transform<Jet> moved;
  for (int i = 0; i < 3; ++i) moved.t[i] = Jet(P.t[i]) + s[i];
  for (int col = 0; col < 3; ++col) {
    const Eigen::Vector3d r = P.R.col(col);
    moved.R(0, col) = Jet(r[0]) + w[1] * r[2] - w[2] * r[1];
    moved.R(1, col) = Jet(r[1]) + w[2] * r[0] - w[0] * r[2];
    moved.R(2, col) = Jet(r[2]) + w[0] * r[1] - w[1] * r[0];
  }
  return moved;
}

bool AnyEffectAt(const std::vector<const Effect*>& effects, EffectStage stage) {
  for (const Effect* e : effects) {
    if (e->stage() == stage) return true;
  }
  return false;
}

void LinearizeJointStage(const std::vector<const Effect*>& effects,
                         const std::vector<int>& effect_sizes, double const* const* effect_params,
                         const EffectContext& context, std::vector<double>* dq,
                         Eigen::MatrixXd* d_dq) {
  const int n = context.num_joints;
  dq->assign(n, 0.0);
  if (d_dq == nullptr) {
    ApplyStage(EffectStage::kJoint, effects, effect_params, context, dq->data());
    return;
  }
  // Joint effects add to dq (effect.h), so each is differentiated alone, over its own
  // parameters: the other stages' effects, and the other joint effects, cost nothing here
  // (the physics finder's linearization carries some fifty candidates at once).
  int total = 0;
  for (int size : effect_sizes) total += size;
  d_dq->setZero(n, total);
  thread_local std::vector<Jet> params, dq_jets;
  for (size_t e = 0, column = 0; e < effects.size(); column += effect_sizes[e++]) {
    if (effects[e]->stage() != EffectStage::kJoint) continue;
    const int size = effect_sizes[e];
    for (int first = 0; first < std::max(1, size); first += kJetStride) {
      params.clear();
      for (int i = 0; i < size; ++i) {
        params.emplace_back(effect_params[e][i]);
        SeedUnit(i, first, &params[i]);
      }
      dq_jets.assign(n, Jet(0.0));
      effects[e]->Apply(context, params.data(), dq_jets.data());
      for (int j = 0; j < n; ++j) {
        if (first == 0) (*dq)[j] += dq_jets[j].a;
        for (int d = 0; d < kJetStride && first + d < size; ++d) {
          (*d_dq)(j, column + first + d) = dq_jets[j].v[d];
        }
      }
    }
  }
}

void LinearizeFlangeStage(const std::vector<const Effect*>& effects,
                          const std::vector<int>& effect_sizes, double const* const* effect_params,
                          const EffectContext& context, Pose* T_base_flange,
                          Eigen::Matrix<double, 6, 6>* motion_map, FlangeTwists* effect_twists) {
  if (motion_map == nullptr || effect_twists == nullptr) {
    double values[12];
    PackPose(*T_base_flange, values);
    ApplyStage(EffectStage::kFlange, effects, effect_params, context, values);
    UnpackPose(values, T_base_flange);
    return;
  }
  // Directions: s (3), w (3), then the flange effects' parameters (the others' columns are zero).
  thread_local EffectParameterJets jets;
  jets.Reset(effects, effect_sizes, effect_params, EffectStage::kFlange, 6);
  const int directions = jets.end_direction();
  FlangeTwists out(6, directions);
  const Pose in = *T_base_flange;
  for (int first = 0; first < directions; first += kJetStride) {
    jets.Seed(first);
    Jet values[12];
    PackPose(FirstOrderMotion(in, first), values);
    ApplyStage(EffectStage::kFlange, effects, jets.pointers(), context, values);
    for (int i = 0; i < 3; ++i) T_base_flange->t[i] = values[i].a;
    for (int col = 0; col < 3; ++col) {
      for (int row = 0; row < 3; ++row) T_base_flange->R(row, col) = values[3 + 3 * col + row].a;
    }
    for (int d = 0; d < kJetStride && first + d < directions; ++d) {
      Eigen::Matrix3d dR;
      for (int col = 0; col < 3; ++col) {
        for (int row = 0; row < 3; ++row) dR(row, col) = values[3 + 3 * col + row].v[d];
      }
      out.col(first + d) << values[0].v[d], values[1].v[d], values[2].v[d],
          TurnOf(dR, T_base_flange->R);
    }
  }
  *motion_map = out.leftCols<6>();
  effect_twists->setZero(6, jets.count());
  jets.ByParameter(out, *effect_twists);
}

}  // namespace cellmetry
