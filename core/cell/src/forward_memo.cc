// One sample's forward kinematics, shared by the blocks that read it (forward_memo.h).
#include "forward_memo.h"

namespace cellmetry {

bool ForwardMemo::Forward(const double* params, Pose* T_base_flange,
                          Eigen::Matrix<double, 6, Eigen::Dynamic>* twists) {
  const bool with_twists = twists != nullptr;
  const size_t n = model_->parameters().size();
  std::lock_guard<std::mutex> lock(mutex_);
  // Equal to the last bit (a NaN never is: made again). Forward and ForwardWithTwists may
  // round differently: each is kept only for itself.
  bool same = made_ && with_twists_ == with_twists && params_.size() == n;
  for (size_t i = 0; same && i < n; ++i) same = params_[i] == params[i];
  if (!same) {
    params_.assign(params, params + n);
    with_twists_ = with_twists;
    ok_ = with_twists ? model_->ForwardWithTwists(q_, params, &T_base_flange_, &twists_)
                      : model_->Forward(q_, params, &T_base_flange_);
    made_ = true;
  }
  if (!ok_) return false;
  *T_base_flange = T_base_flange_;
  if (with_twists) *twists = twists_;
  return true;
}

}  // namespace cellmetry
