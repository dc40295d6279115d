// The warnings of a cell's identification (workcell_warnings.h): what a result's user is told
// beside its numbers.
#include "workcell_warnings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <utility>

#include "cellmetry/basics/plausibility.h"
#include "cellmetry/basics/text.h"
#include "cellmetry/cell/motion_check.h"

namespace cellmetry {
namespace {

// A job's effect fitted beyond the size its physics plausibly has (JudgePlausibility), or below
// zero by more than three sigma where its physics cannot be negative (plausible_nonnegative;
// within three sigma it is zero and noise): the fit may be using it for something else with its
// signature, so the user is told before a robot controller is.
void AddImplausibleEffectWarnings(const WorkcellProblem& spec, WorkcellResult* result) {
  const char* look_alikes =
      "the fit uses it for something else with the same signature; "
      "docs/physics.md lists look-alikes";
  for (const WorkcellEffect& effect : spec.effects) {
    std::vector<Parameter> fitted;
    std::vector<double> values, sigmas;
    for (const Parameter& p : effect.effect->parameters()) {
      for (const ScalarEstimate& s : result->model_parameters) {
        if (s.name != effect.name + "." + p.name || s.held) continue;
        fitted.push_back(p);
        values.push_back(s.value);
        sigmas.push_back(s.sigma);
      }
    }
    std::vector<double> margins;
    for (double sigma : sigmas) margins.push_back(3 * sigma);
    for (const PlausibilityFinding& f : JudgePlausibility(fitted, values, margins)) {
      const std::string what = PlausibilityText(fitted, values, f, effect.name + ".");
      char sigma[64];
      std::snprintf(sigma, sizeof sigma, " (+- %.2g)", sigmas[f.index]);
      result->warnings.push_back(
          f.kind == Plausibility::kBelowZero
              ? what + sigma + ": " + look_alikes
              : "beyond the size its physics plausibly has: " + what + sigma +
                    "; either that physics is larger here than expected, or " + look_alikes);
    }
  }
}

// A carried target whose rotation the job frees but does not fit (use_tool_rotation: false):
// held as unidentifiable, which the estimation can explain only as "no measurement depends on
// it", while the recording may well measure it.
void AddUnfittedToolRotationWarning(const WorkcellProblem& spec, WorkcellResult* result) {
  if (spec.use_tool_rotation) return;
  std::string targets;
  for (const WorkcellRobot& robot : spec.robots) {
    for (const WorkcellTool& tool : robot.tools) {
      if (tool.is_camera()) continue;  // eye in hand: its rotations are always fitted
      const std::array<bool, 6>& free = tool.flange_tool.free;
      if (free[3] || free[4] || free[5]) targets += (targets.empty() ? "" : ", ") + tool.target;
    }
  }
  if (targets.empty()) return;
  result->warnings.push_back(
      "the job frees the rotation of " + targets +
      ", but fits the carried targets' positions "
      "only (use_tool_rotation: false), so the rotation was held at its nominal value: set "
      "use_tool_rotation: true to fit the rotations the recording measures, or free [x, y, z]");
}

// The far starts as "<frame>'s <mm> mm and <rad> rad", comma-separated.
std::string FarStartWords(const std::vector<FarStart>& far) {
  std::string words;
  for (const FarStart& f : far) {
    char line[160];
    std::snprintf(line, sizeof line, "%s's %.0f mm and %.2f rad", f.frame.c_str(), f.distance_mm,
                  f.angle_rad);
    words += (words.empty() ? "" : ", ") + std::string(line);
  }
  return words;
}

}  // namespace

void AddModelWarnings(const WorkcellProblem& spec, WorkcellResult* result) {
  for (const WorkcellRobot& robot : spec.robots) {
    const bool model_free =
        std::any_of(robot.model_parameters.begin(), robot.model_parameters.end(),
                    [](const Parameter& p) { return !p.fixed; });
    if (!model_free) continue;
    for (const auto& w : robot.model->Warnings(robot.model_parameters)) {
      result->warnings.push_back(robot.name + ": " + w);
    }
  }
}

void AddWarnings(const WorkcellProblem& spec, WorkcellResult* result) {
  if (!result->solver.converged) {
    result->warnings.push_back(
        "the solver stopped before converging (" + result->solver.stop_reason +
        "): the answer may not be the best fit; raise the solver's max_iterations, or give "
        "starts nearer the truth");
  }
  AddUnfittedToolRotationWarning(spec, result);
  result->weakly_identified = WeaklyIdentified(result->uncertainty, spec.weak_vif);
  if (!result->weakly_identified.empty()) {
    std::string names;
    for (const auto& w : result->weakly_identified) names += (names.empty() ? "" : ", ") + w.name;
    result->warnings.push_back("this data barely identifies " + names +
                               ": they move together; record poses that vary them "
                               "independently (other heights, the workspace's edges)");
  }
  AddImplausibleEffectWarnings(spec, result);
  if (result->uncertainty.reduced_chi2 > 4.0) {
    result->warnings.push_back(
        "residuals are " +
        std::to_string(std::sqrt(result->uncertainty.reduced_chi2)).substr(0, 4) +
        "x the stated noise: the model leaves something out; uncertainties were scaled up");
  }
}

void AddStillJointWarnings(const WorkcellProblem& spec, const Recording& recording,
                           const WorkcellData& data, WorkcellResult* result) {
  for (std::string& still : StillJoints(spec, recording, data)) {
    result->warnings.push_back(std::move(still));
  }
}

void AddCameraLeftOutWarnings(WorkcellResult* result) {
  for (const CameraLeftOut& c : result->cameras_left_out) {
    if (!c.error.empty()) {
      result->warnings.push_back("without " + c.camera + " the cell cannot be identified (" +
                                 c.error + "): nothing checks what it alone determines");
    } else if (c.flagged()) {
      char sigmas[32];
      std::snprintf(sigmas, sizeof sigmas, "%.1f", c.worst_sigmas);
      result->warnings.push_back(
          "without " + c.camera + " " + c.worst + " moves by " + sigmas +
          " sigma of the "
          "difference: " +
          c.camera +
          " disagrees with the other cameras beyond the "
          "uncertainty (its intrinsics, its mount or the model's camera-side physics)");
    }
  }
}

void AddFarStartWarning(const std::vector<FarStart>& far, std::optional<double> given_mm,
                        const std::string& given_failure, double own_mm, bool same, bool kept_given,
                        WorkcellResult* kept) {
  char line[480];
  const std::string from_given =
      given_mm ? Mm(*given_mm, 4) + " RMS" : "a failed fit (" + given_failure + ")";
  std::snprintf(line, sizeof line,
                "the job's start lies far from where the data put the frame (%s from the "
                "closed-form start); fitted from both: the carried targets are predicted to "
                "%s from the given start, %.4g mm RMS from the data's own: %s",
                FarStartWords(far).c_str(), from_given.c_str(), own_mm,
                same         ? "the same answer, kept"
                : kept_given ? "the given start's answer kept"
                             : "the data's answer kept. Check the start in the job");
  kept->warnings.push_back(line);
}

}  // namespace cellmetry
