// A frame block's pose and left Jacobian, computed once per thread for the values at hand
// (internal to the cell layer).
//
// Every residual of a cell reads the same few frame blocks (a base, a tool, three cameras on
// exp_a) at the same values within one evaluation, and ChainCost turned each into a rotation
// (Rodrigues: a sine, a cosine, a matrix product) and a left Jacobian again for every one of its
// 22,500 residual blocks: a sixth of the identification's time. This remembers the last few by
// what they are a function of (the six values and R_ref), so the answer is the same bits as
// computing it: a hit needs every input equal, a miss computes and takes the oldest slot.
// Per thread, since Ceres and EvaluateSparse evaluate blocks on several at once.
#pragma once

#include <Eigen/Core>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

struct CachedFrame {
  Pose T;                  // FrameFromBlock(block, R_ref)
  Eigen::Matrix3d J_left;  // LeftJacobian of the block's rotation part (with_jacobian only)
};

// FrameFromBlock(block, R_ref) and, when `with_jacobian`, LeftJacobian(block + 3) (a copy:
// the next call may take the slot).
CachedFrame FrameOfBlock(const double* block, const Eigen::Matrix3d& R_ref, bool with_jacobian);

}  // namespace cellmetry
