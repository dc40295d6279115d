// Plausibility of an effect's values, judged together (plausibility.h).
#include "cellmetry/basics/plausibility.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>
#include <string>

namespace cellmetry {
namespace {

// The members (indices) of each plausible_group with two or more among the first `count`.
std::map<std::string, std::vector<size_t>> Groups(const std::vector<Parameter>& parameters,
                                                  size_t count) {
  std::map<std::string, std::vector<size_t>> groups;
  for (size_t i = 0; i < count; ++i) {
    if (!parameters[i].plausible_group.empty()) groups[parameters[i].plausible_group].push_back(i);
  }
  for (auto it = groups.begin(); it != groups.end();) {
    it = it->second.size() < 2 ? groups.erase(it) : std::next(it);
  }
  return groups;
}

}  // namespace

std::vector<PlausibilityFinding> JudgePlausibility(const std::vector<Parameter>& parameters,
                                                   const std::vector<double>& values,
                                                   const std::vector<double>& margins) {
  const size_t count = std::min(parameters.size(), values.size());
  const auto groups = Groups(parameters, count);
  std::vector<PlausibilityFinding> found;
  for (size_t i = 0; i < count; ++i) {
    const Parameter& p = parameters[i];
    const double margin = i < margins.size() ? margins[i] : 0.0;
    if (PlausibilityOf(p, values[i], margin) == Plausibility::kBelowZero) {
      found.push_back(
          {i, PlausibilityFinding::Part::kValue, Plausibility::kBelowZero, values[i], 0.0, 0.0});
      continue;
    }
    const auto group = groups.find(p.plausible_group);
    if (group == groups.end()) {
      if (PlausibilityOf(p, values[i]) == Plausibility::kTooLarge) {
        found.push_back({i, PlausibilityFinding::Part::kValue, Plausibility::kTooLarge, values[i],
                         *p.plausible, 0.0});
      }
      continue;
    }
    double mean = 0.0;
    for (size_t k : group->second) mean += values[k];
    mean /= static_cast<double>(group->second.size());
    if (i == group->second.front() && p.plausible_common && std::abs(mean) > *p.plausible_common) {
      found.push_back({i, PlausibilityFinding::Part::kCommon, Plausibility::kTooLarge, mean,
                       *p.plausible_common, mean});
    }
    if (p.plausible && std::abs(values[i] - mean) > *p.plausible) {
      found.push_back({i, PlausibilityFinding::Part::kDeparture, Plausibility::kTooLarge,
                       values[i] - mean, *p.plausible, mean});
    }
  }
  return found;
}

std::string PlausibilityText(const std::vector<Parameter>& parameters,
                             const std::vector<double>& values, const PlausibilityFinding& found,
                             const std::string& prefix) {
  const Parameter& p = parameters[found.index];
  const std::string name = prefix + p.name;
  char text[400];
  if (found.kind == Plausibility::kBelowZero) {
    std::snprintf(text, sizeof text, "%s = %.3g %s, below zero, which this physics cannot be",
                  name.c_str(), values[found.index], p.unit.c_str());
  } else if (found.part == PlausibilityFinding::Part::kValue) {
    std::snprintf(text, sizeof text, "%s = %.3g %s, where this physics is typically below %.3g",
                  name.c_str(), values[found.index], p.unit.c_str(), found.bound);
  } else if (found.part == PlausibilityFinding::Part::kDeparture) {
    std::snprintf(text, sizeof text,
                  "%s = %.3g %s, %.3g off the %.3g its group (%s) shares, where one alone "
                  "typically departs below %.3g",
                  name.c_str(), values[found.index], p.unit.c_str(), found.judged, found.mean,
                  p.plausible_group.c_str(), found.bound);
  } else {
    std::snprintf(text, sizeof text,
                  "the %s shared by %s and the others = %.3g %s, where a cause they share is "
                  "typically below %.3g",
                  p.plausible_group.c_str(), name.c_str(), found.mean, p.unit.c_str(), found.bound);
  }
  return text;
}

}  // namespace cellmetry
