// JudgePlausibility: how an effect's fitted values stand against the sizes their physics
// plausibly has (Parameter::plausible, plausible_nonnegative, plausible_group), judged together,
// so that a cause several parameters share (every camera's principal point shifted alike) is
// judged as one cause and each one's own part as its own. The physics finder refuses a finding
// by it; `run` warns by it.
#pragma once

#include <string>
#include <vector>

#include "cellmetry/basics/parameter.h"

namespace cellmetry {

// What one judgement found beyond its bound.
struct PlausibilityFinding {
  enum class Part {
    kValue,      // the value itself
    kDeparture,  // its departure from its group's mean (`plausible`)
    kCommon,     // its group's mean (`plausible_common`); reported once, at the group's first
  };
  size_t index = 0;  // the parameter (the group's first, for kCommon)
  Part part = Part::kValue;
  Plausibility kind = Plausibility::kTooLarge;
  double judged = 0.0;  // the value, the departure or the mean
  double bound = 0.0;   // what it is judged against (0 for kBelowZero)
  double mean = 0.0;    // the group's mean (kDeparture, kCommon)
};

// Every finding among `values` (one per parameter, in order), in parameter order. `margins`
// (per parameter, optional): how far below zero a value may lie where its physics has a sign
// before it counts (three sigma in `run`: within it, zero and noise).
std::vector<PlausibilityFinding> JudgePlausibility(const std::vector<Parameter>& parameters,
                                                   const std::vector<double>& values,
                                                   const std::vector<double>& margins = {});

// The finding in words: "cam2.principal_y = -0.0301 rad, where this physics is typically below
// 0.02"; for a group, what it shares and what is its own ("..., 0.0111 rad off the -0.019 its
// group shares, where one alone typically departs below 0.02"). `prefix` goes before each
// parameter's name (an effect's name and a dot, or nothing).
std::string PlausibilityText(const std::vector<Parameter>& parameters,
                             const std::vector<double>& values, const PlausibilityFinding& found,
                             const std::string& prefix = "");

}  // namespace cellmetry
