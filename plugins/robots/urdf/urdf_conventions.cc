// HeldByConvention (urdf_conventions.h).
#include "urdf_conventions.h"

#include <cmath>

#include "urdf_model.h"

namespace cellmetry::urdf_robot {

namespace {

constexpr int kTranslation = kX;  // x y z
constexpr int kRotation = kRoll;  // roll pitch yaw

// Of the three coordinates from `first` on (x y z or roll pitch yaw) not yet held, the one where
// `direction` is largest: holding it removes that direction best. -1 when all three are held (a
// chain of one joint, held whole).
int BestCoordinate(const Eigen::Vector3d& direction, int first,
                   const std::vector<std::string>& held, size_t joint) {
  int best = -1;
  double largest = -1.0;
  for (int k = 0; k < 3; ++k) {
    if (!held[kParamsPerJoint * joint + first + k].empty()) continue;
    if (std::abs(direction[k]) > largest) {
      largest = std::abs(direction[k]);
      best = k;
    }
  }
  return best < 0 ? -1 : first + best;
}

}  // namespace

std::vector<std::string> HeldByConvention(const UrdfChain& chain) {
  const size_t n = chain.joints.size();
  std::vector<std::string> held(kParamsPerJoint * n);
  auto hold = [&](size_t joint, int entry, const std::string& why) {
    if (entry < 0) return;
    std::string& slot = held[kParamsPerJoint * joint + entry];
    if (slot.empty()) slot = why;
  };
  const std::string first = chain.joints[0].name;
  for (int entry = 0; entry < kParamsPerJoint; ++entry) {
    hold(0, entry, "with " + first + "'s axis it puts the base frame");
  }
  for (size_t i = 1; i < n; ++i) {
    const UrdfJoint& joint = chain.joints[i];
    const std::string& previous = chain.joints[i - 1].name;
    // Joint i-1's axis and a point on it (its frame's origin), in joint i's parent link.
    const Pose T_parent_previous = joint.T_previous_parent.inverse();
    const Eigen::Vector3d previous_axis = T_parent_previous.R * chain.joints[i - 1].axis;
    const Eigen::Vector3d previous_point = T_parent_previous.t;
    // A shift along the previous axis.
    const int shift = BestCoordinate(previous_axis, kTranslation, held, i);
    hold(i, shift,
         "a shift along " + previous + "'s axis, which " + previous + "'s origin carries");
    // A turn about its own axis (the joint frame's axis: exactly the offset).
    const int own_turn = BestCoordinate(joint.axis, kRotation, held, i);
    hold(i, own_turn, "a turn about " + joint.name + "'s own axis, which its offset carries");
    // A turn of this origin about the previous axis, seen in the joint frame.
    const Eigen::Vector3d previous_axis_in_joint = joint.R_parent_joint.transpose() * previous_axis;
    const Eigen::Vector3d across = previous_axis_in_joint.cross(joint.axis);
    if (across.norm() > 1e-3) {
      // The turn's part independent of the own axis, held where it is largest.
      const Eigen::Vector3d rest =
          previous_axis_in_joint - previous_axis_in_joint.dot(joint.axis) * joint.axis;
      hold(i, BestCoordinate(rest, kRotation, held, i),
           "a turn about " + previous + "'s axis, which " + previous + ".offset carries");
      continue;
    }
    // Parallel: the turn is one about this axis plus a shift across both axes.
    const Eigen::Vector3d around = previous_axis.cross(joint.xyz_mm - previous_point);
    if (around.norm() > 1e-3) {
      hold(i, BestCoordinate(around, kTranslation, held, i),
           "where " + joint.name + "'s axis stands about the parallel axis of " + previous +
               ", which " + previous + ".offset carries");
    } else {
      hold(i, kOffset,
           "on the line of " + previous + "'s axis, " + previous +
               ".offset carries a turn about it");
    }
  }
  const size_t last = n - 1;
  const UrdfJoint& tip = chain.joints[last];
  const std::string flange = "with " + tip.name + "'s axis it puts the flange frame";
  hold(last, kOffset, flange);
  hold(last, BestCoordinate(tip.R_parent_joint * tip.axis, kTranslation, held, last), flange);
  return held;
}

}  // namespace cellmetry::urdf_robot
