// Parameter: one named scalar that a calibration can estimate or hold.
//
// Every quantity cellmetry identifies (a base-frame coordinate, a link length, a joint offset, a
// camera position) is a Parameter with its unit. A job decides which are free; the rest stay at
// their nominal value. Bounds and a prior (a Gaussian on the nominal value with sigma
// `prior_sigma`) are optional.
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace cellmetry {

struct Parameter {
  std::string name;      // e.g. "x", "j2.d" (unique within its block)
  std::string unit;      // "mm", "rad" or "1"
  double nominal = 0.0;  // starting value, and the value held when fixed
  bool fixed = false;
  std::optional<double> lower;
  std::optional<double> upper;
  std::optional<double> prior_sigma;  // same unit as the parameter
  std::string description;            // one line, for `cellmetry plugins` and reports
  // |value| beyond which the physics it stands for is unusual (effects, effect.h): a finding
  // that large is flagged in the report, not bounded.
  std::optional<double> plausible;
  // True where a value below zero has no physics (a compliance: a joint that gives against
  // gravity; a play or a clearance): such a finding is flagged as `plausible` flags a size.
  bool plausible_nonnegative = false;
  // Where parameters of one effect share a `plausible_group` (each camera's principal point x in
  // an effect over several cameras), a cause they share can plausibly be larger than one of
  // them alone: their mean is judged against `plausible_common` and each one's departure from
  // the mean against `plausible` (JudgePlausibility, plausibility.h). Alone in its group, a
  // parameter is judged as any other.
  std::string plausible_group = "";
  std::optional<double> plausible_common = std::nullopt;
  // Non-empty where holding the parameter at its nominal value is a convention rather than an
  // answer: what the value puts where (a robot's first-joint parameters put its base frame, the
  // last joint's put its flange frame, a redundant Hayati tilt is zero by definition). Where the
  // data cannot determine a direction, such a parameter is held before any other of it, and the
  // frames and parameters that move with it are reported relative to it, not as undetermined.
  std::string convention = "";
};

// How a fitted value stands against its physics (`plausible`, `plausible_nonnegative`): below
// zero by more than `below_zero_margin` (the value's unit) where the physics has a sign, beyond
// its plausible size, or plausible. The physics finder and `run`'s warnings both judge by it.
enum class Plausibility { kPlausible, kBelowZero, kTooLarge };
inline Plausibility PlausibilityOf(const Parameter& p, double value,
                                   double below_zero_margin = 0.0) {
  if (p.plausible_nonnegative && value < -below_zero_margin) return Plausibility::kBelowZero;
  if (p.plausible && std::abs(value) > *p.plausible) return Plausibility::kTooLarge;
  return Plausibility::kPlausible;
}

// Index of the parameter called `name` in `params`, or -1.
int FindParameter(const std::vector<Parameter>& params, const std::string& name);

}  // namespace cellmetry
