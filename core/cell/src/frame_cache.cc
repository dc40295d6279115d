// A frame block's pose and left Jacobian, once per thread for the values at hand (frame_cache.h).
#include "frame_cache.h"

#include <algorithm>
#include <array>

#include "cellmetry/basics/so3_jacobians.h"
#include "cellmetry/model/frame_block.h"

namespace cellmetry {
namespace {

struct Slot {
  std::array<double, 6> values{};
  Eigen::Matrix3d R_ref = Eigen::Matrix3d::Zero();
  bool used = false;
  bool has_jacobian = false;
  CachedFrame frame;
};

// Enough for every frame block one residual family reads (a base, its tools, the cameras);
// more only costs a longer search.
constexpr int kSlots = 8;

struct Table {
  std::array<Slot, kSlots> slots;
  int next = 0;  // the slot a miss takes (round robin: the oldest)
};

// Equal inputs to the last bit (NaN never equals: always computed again).
bool Holds(const Slot& slot, const double* block, const Eigen::Matrix3d& R_ref) {
  if (!slot.used) return false;
  for (int i = 0; i < 6; ++i) {
    if (slot.values[i] != block[i]) return false;
  }
  for (int i = 0; i < 9; ++i) {
    if (slot.R_ref.data()[i] != R_ref.data()[i]) return false;
  }
  return true;
}

}  // namespace

CachedFrame FrameOfBlock(const double* block, const Eigen::Matrix3d& R_ref, bool with_jacobian) {
  thread_local Table table;
  Slot* slot = nullptr;
  for (Slot& s : table.slots) {
    if (Holds(s, block, R_ref)) {
      slot = &s;
      break;
    }
  }
  if (slot == nullptr) {
    slot = &table.slots[table.next];
    table.next = (table.next + 1) % kSlots;
    std::copy(block, block + 6, slot->values.begin());
    slot->R_ref = R_ref;
    slot->used = true;
    slot->has_jacobian = false;
    slot->frame.T = FrameFromBlock(block, R_ref);
  }
  if (with_jacobian && !slot->has_jacobian) {
    slot->frame.J_left = LeftJacobian(Eigen::Vector3d(block[3], block[4], block[5]));
    slot->has_jacobian = true;
  }
  return slot->frame;
}

}  // namespace cellmetry
