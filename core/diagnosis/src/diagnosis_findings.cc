// Physical findings (diagnosis.h, step 7): the accepted effects grouped by the site they act at,
// each group headed by its best single description, each further member named as separate
// physics only where it removes a material share of what the group removes or does not look
// like the headline.
#include <algorithm>
#include <map>

#include "cellmetry/diagnosis/diagnosis.h"

namespace cellmetry {
namespace {

// The one entry of `config[key]` (a sequence or a scalar), or "" where it has none or several.
std::string OnlyEntry(const ConfigNode& config, const std::string& key) {
  if (!config.IsMap() || !config.Has(key)) return "";
  const ConfigNode node = config[key];
  if (node.IsScalar()) return node.AsString();
  if (!node.IsSequence()) return "";
  const std::vector<ConfigNode> entries = node.Elements();
  return entries.size() == 1 && entries[0].IsScalar() ? entries[0].AsString() : "";
}

// What a model's held-out fit leaves beyond the floor: mean square in sigmas minus one.
double Excess(double held_out_sigma) { return held_out_sigma * held_out_sigma - 1.0; }

}  // namespace

std::string CandidateSite(const ConfigNode& config, const std::string& robot) {
  if (const std::string joint = OnlyEntry(config, "joints"); !joint.empty()) {
    return robot + " joint " + joint;
  }
  if (const std::string arm = OnlyEntry(config, "arms"); !arm.empty()) return robot + " arm " + arm;
  if (const std::string camera = OnlyEntry(config, "cameras"); !camera.empty()) {
    return "camera " + camera;
  }
  for (const std::string key : {"targets", "target"}) {
    if (const std::string target = OnlyEntry(config, key); !target.empty()) {
      return "target " + target;
    }
  }
  return "";
}

void GroupFindings(const DiagnosisOptions& options, DiagnosisResult* result) {
  std::vector<AcceptedEffect>& accepted = result->accepted;
  result->findings.clear();
  result->min_group_share = options.min_group_share;
  result->shape_correlation = options.shape_correlation;
  std::map<std::string, size_t> finding_of_site;
  for (size_t i = 0; i < accepted.size(); ++i) {
    const std::string& site = accepted[i].site;
    const auto it = site.empty() ? finding_of_site.end() : finding_of_site.find(site);
    if (it == finding_of_site.end()) {
      if (!site.empty()) finding_of_site[site] = result->findings.size();
      PhysicalFinding f;
      f.site = site;
      f.headline = static_cast<int>(i);
      result->findings.push_back(f);
      continue;
    }
    result->findings[it->second].separate.push_back(static_cast<int>(i));  // sorted below
  }
  // What each member removed at its own acceptance, and the group's sum: the group's members
  // need not be accepted in consecutive rounds, so the sum of their own gains, not the span.
  for (PhysicalFinding& f : result->findings) {
    std::vector<int> members = {f.headline};
    members.insert(members.end(), f.separate.begin(), f.separate.end());
    std::map<int, double> removed;
    f.held_out_excess_removed = 0.0;
    for (int m : members) {
      removed[m] = std::max(0.0, Excess(accepted[m].held_out_sigma_before) -
                                     Excess(accepted[m].held_out_sigma_after));
      f.held_out_excess_removed += removed[m];
    }
    f.separate.clear();  // refilled with those that pass
    const auto& correlations = accepted[f.headline].site_correlations;
    for (int m : members) {
      AcceptedEffect& a = accepted[m];
      a.group_share = f.held_out_excess_removed > 0 ? removed[m] / f.held_out_excess_removed : 0.0;
      // Every later member was a testable candidate in the headline's round (an untestable one
      // is never tried again); one missing there cannot be said to look like it.
      const auto c = correlations.find(a.name);
      a.headline_correlation = m == f.headline ? 1.0 : c != correlations.end() ? c->second : 0.0;
      if (m == f.headline) {
        a.role = "headline";
      } else if (a.group_share >= options.min_group_share ||
                 a.headline_correlation < options.shape_correlation) {
        a.role = "separate";
        f.separate.push_back(m);
      } else {
        a.role = "residual shape";
        f.residual_shape.push_back(m);
      }
    }
  }
}

}  // namespace cellmetry
