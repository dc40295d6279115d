// Closed-form rigid fit between matched point sets (Kabsch 1976; Umeyama 1991 without scale).
//
// FitRigidTransform returns T_to_from minimising sum |to_i - T * from_i|^2 (Eigen::umeyama). It
// needs at least three finite points that are not all on one line; otherwise std::nullopt.
#pragma once

#include <optional>
#include <vector>

#include "cellmetry/basics/transform.h"

namespace cellmetry {

std::optional<Pose> FitRigidTransform(const std::vector<Eigen::Vector3d>& from,
                                      const std::vector<Eigen::Vector3d>& to);

// FitRigidTransform onto the same `to` again and again (the closed-form start's alternation fits
// its base afresh each round onto the same world points): `to` is copied and checked once, not
// in every round. The same answers.
class RigidFitOnto {
 public:
  explicit RigidFitOnto(const std::vector<Eigen::Vector3d>& to);
  std::optional<Pose> Fit(const std::vector<Eigen::Vector3d>& from) const;

 private:
  Eigen::Matrix3Xd to_;
  bool usable_ = false;  // finite and not all on one line
};

}  // namespace cellmetry
