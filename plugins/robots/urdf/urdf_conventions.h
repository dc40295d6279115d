// Which of a URDF arm's joint-origin parameters (urdf_model.h) are held by convention, and why.
//
// A movable joint turns the rest of the arm about its axis, so what commutes with that turn, a
// turn about the axis and a shift along it, can sit on either side of the joint: at the joint's
// own origin (the end nearer the base), in its offset, or at the next joint's origin. End-effector
// poses see only the sum, and all but one are held (Parameter::convention). For joint i, in the
// frames its parameters are written in (x y z in its parent link, roll pitch yaw in the joint
// frame), the held coordinate is the one that carries the most of the direction held:
//
//   joint 1       all seven: with its axis they put the base frame (a free base absorbs them)
//   every joint   the turn about its own axis (its offset carries it)
//   joint i > 1   the shift along joint i-1's axis (joint i-1's origin carries it); the turn
//                 about joint i-1's axis (joint i-1's offset carries it); where the two axes
//                 are parallel that turn is a turn about the axis plus a shift, so the shift
//                 about joint i-1's axis is held instead (where this axis stands about it);
//                 where they are one line, the offset
//   last joint    its offset and its shift along its own axis: they put the flange frame
//
// That leaves 4 per joint between the first and the last and 2 on the last, as many as the
// modified-DH table frees (18 on a six-joint arm), and the rest well conditioned at the URDF's
// geometry. Two consecutive parallel axes at the end of the chain are not covered: there the
// fit's own degeneracy check holds what is left (estimation_quality.h).
#pragma once

#include <string>
#include <vector>

#include "urdf_chain.h"

namespace cellmetry::urdf_robot {

// One entry per parameter (kParamsPerJoint per joint, urdf_model.h): "" where the parameter is
// free, else what holding it at nominal puts where.
std::vector<std::string> HeldByConvention(const UrdfChain& chain);

}  // namespace cellmetry::urdf_robot
