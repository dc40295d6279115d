// The physics finder's report (diagnosis.h): ten seconds of words, and the same in JSON.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cellmetry/basics/text.h"
#include "cellmetry/diagnosis/diagnosis.h"
#include "cellmetry/formats/fixed_number.h"

namespace cellmetry {
namespace {

// A failed test (CandidateFinding::failed) in words.
std::string Why(const CandidateFinding& f, const std::string& test) {
  if (test == "size") return "its fitted size rules it out (" + f.implausible + ")";
  if (test == "share") {
    return "it removes " + FixedNumber(100 * f.explained_share, 0) +
           " % of the held-out excess over the floor, a sliver of something else";
  }
  if (test == "LR") return "its likelihood-ratio test fails after Holm's correction";
  if (test == "positions") return "it makes the held-out positions worse";
  if (test == "BIC") return "BIC does not fall";
  if (test == "CV") return "its held-out gain is within its standard error";
  if (test == "rivals") {
    if (f.rival_p >= 1.0) return f.rival + " explains the data at least as strongly";
    return "were " + f.rival + " the cause, a margin this large would come " +
           FixedNumber(100 * f.rival_p, 1) + " % of the time";
  }
  std::string why = "the bootstrap includes it in " + FixedNumber(100 * f.bootstrap_share, 0) +
                    " % of resamples, not 80 %";
  if (!f.bootstrap_rival.empty()) why += " (" + f.bootstrap_rival + " competes)";
  return why;
}

// The last round of the physics (not the frames' step after it); null when there is none.
const DiagnosisRound* LastPhysicsRound(const DiagnosisResult& r) {
  const auto it = std::find_if(r.rounds.rbegin(), r.rounds.rend(),
                               [](const DiagnosisRound& round) { return !round.frames; });
  return it == r.rounds.rend() ? nullptr : &*it;
}

// Where the closest candidate passed every test but the one against its rival (the rival test,
// or the bootstrap's split) and the rival acts at the same joint or camera, that rival: a finding
// at the site with two names. Something is there; these poses cannot say which of the two it is.
// Null otherwise.
const CandidateFinding* TiedRival(const DiagnosisRound& round, const CandidateFinding& f) {
  const bool rivals = f.failed == std::vector<std::string>{"rivals"};
  const bool bootstrap = f.failed == std::vector<std::string>{"bootstrap"};
  if ((!rivals && !bootstrap) || f.site.empty()) return nullptr;
  const std::string& rival = rivals ? f.rival_effect : f.bootstrap_rival_effect;
  const auto other = std::find_if(round.candidates.begin(), round.candidates.end(),
                                  [&](const CandidateFinding& c) { return c.name == rival; });
  if (other == round.candidates.end() || other->site != f.site) return nullptr;
  return &*other;
}

std::string TieAtItsSite(const DiagnosisRound& round, const CandidateFinding& f) {
  const CandidateFinding* other = TiedRival(round, f);
  if (!other) return "";
  return "Tied at " + f.site + ": " + f.label + " or " + other->label +
         ". Something of either shape is there (the closest passes every other test); these "
         "poses cannot say which.";
}

// 0.1382, 0.0078 -> "0.138 +- 0.0078 mm".
std::string MmWithSe(double value_mm, double se_mm) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.3g +- %.2g mm", value_mm, se_mm);
  return b;
}

std::string Value(const ScalarEstimate& s) {
  char b[96];
  std::snprintf(b, sizeof(b), "%s = %.3g +- %.2g %s", s.name.c_str(), s.value, s.sigma,
                s.unit.c_str());
  return b;
}

// One accepted effect's aliases, its other look-alikes (at most three) and parameters, indented.
void Details(const AcceptedEffect& a, std::ostringstream& out) {
  if (!a.aliases.empty()) {
    out << "  In these poses it is indistinguishable from";
    for (size_t i = 0; i < a.aliases.size(); ++i) out << (i ? "," : "") << " " << a.aliases[i];
    out << "; poses that tell them apart would settle which.\n";
  }
  std::vector<LookAlike> others;
  for (const LookAlike& l : a.look_alikes) {
    const bool alias = std::find(a.aliases.begin(), a.aliases.end(), l.label) != a.aliases.end();
    if (!alias && others.size() < 3) others.push_back(l);
  }
  if (!others.empty()) {
    out << "  In these poses it looks like";
    for (size_t i = 0; i < others.size(); ++i) {
      out << (i ? "," : "") << " " << others[i].label << " ("
          << FixedNumber(others[i].correlation, 2) << ")";
    }
    out << ": the tests preferred this name, and poses that tell them apart would confirm it.\n";
  }
  if (!a.stronger_implausible.empty()) {
    out << "  A stronger fit of this mismatch needs a size its physics cannot have ("
        << a.stronger_implausible.front()
        << "): what causes it may be larger than this name explains.\n";
  }
  for (const auto& p : a.parameters) out << "  " << Value(p) << "\n";
}

// A further effect of a finding that passed its test against the group: another form of the
// headline's cause (a camera's focal length beside its distortion), or separate physics at the
// same site.
void SeparateMember(const DiagnosisResult& r, const PhysicalFinding& f, const AcceptedEffect& head,
                    const AcceptedEffect& a, std::ostringstream& out) {
  const std::string share = FixedNumber(100 * a.group_share, 1) + " % of what the finding removes";
  if (!a.group.empty() && a.group == head.group) {
    out << "  Also part of " << head.group_label << ": " << a.description << " (up to "
        << Mm(a.peak_mm) << "; " << share << ").\n";
  } else {
    out << "  Also at " << f.site << ", separate physics: " << a.description << " (up to "
        << Mm(a.peak_mm) << "; " << share;
    if (a.group_share >= r.min_group_share) {
      out << ", at least " << FixedNumber(100 * r.min_group_share, 0) << " %).\n";
    } else {
      out << ", but unlike the physics above: correlation "
          << FixedNumber(a.headline_correlation, 2) << " with its signature, under "
          << FixedNumber(r.shape_correlation, 2) << ").\n";
    }
  }
  Details(a, out);
}

// One physical finding (diagnosis.h, step 7): its headline, then the further effects fitted at
// the same site, each as separate physics or as the headline physics' residual shape, with the
// share of the group's held-out excess that decided it.
void Finding(const DiagnosisResult& r, const PhysicalFinding& f, std::ostringstream& out) {
  const AcceptedEffect& head = r.accepted[f.headline];
  out << "Left out: ";
  // A group's forms are pieces of one cause: the cause first, the form as its best description.
  if (!head.group_label.empty()) out << head.group_label << ", best described as ";
  out << head.description;
  if (head.frame) {
    out << ", a frame the job's stated level determines: it moves where the answer is read, not "
           "what the model predicts, so held-out error cannot judge it; its likelihood-ratio test "
           "and its size did";
  } else {
    out << " (up to " << Mm(head.peak_mm) << " at the tool)";
  }
  const size_t members = 1 + f.separate.size() + f.residual_shape.size();
  if (members > 1) {
    out << "; one finding at " << f.site << " with the effects below (this one removes "
        << FixedNumber(100 * head.group_share, 1) << " % of what they remove together from the "
        << "held-out excess)";
  }
  out << ".\n";
  Details(head, out);
  for (int m : f.separate) SeparateMember(r, f, head, r.accepted[m], out);
  for (int m : f.residual_shape) {
    const AcceptedEffect& a = r.accepted[m];
    out << "  Also fitted at " << f.site << ": " << a.label << " (up to " << Mm(a.peak_mm) << "), "
        << FixedNumber(100 * a.group_share, 1) << " % of what the finding removes, under "
        << FixedNumber(100 * r.min_group_share, 0) << " %, and like the physics above (correlation "
        << FixedNumber(a.headline_correlation, 2) << "): its residual shape (its real form differs "
        << "from the library's), not separate physics.\n";
    Details(a, out);
  }
}

// `r`, its accepted effects grouped into findings if whoever made it did not (a result built by
// hand, not by DiagnoseWorkcell): every accepted effect is shown as part of some finding.
const DiagnosisResult& Grouped(const DiagnosisResult& r, DiagnosisResult* storage) {
  if (!r.findings.empty() || r.accepted.empty()) return r;
  *storage = r;
  DiagnosisOptions options;
  options.min_group_share = r.min_group_share;
  options.shape_correlation = r.shape_correlation;
  GroupFindings(options, storage);
  return *storage;
}

// Each round whose strongest refit (the largest likelihood ratio) was ruled out by its size: what
// fits best, how large it would have to be and its plausible bound, before any name is read.
void StrongestRuledOut(const DiagnosisResult& r, std::ostringstream& out) {
  for (size_t k = 0; k < r.rounds.size(); ++k) {
    const CandidateFinding* strongest = nullptr;
    for (const auto& f : r.rounds[k].candidates) {
      if (!f.refitted) continue;
      if (!strongest || f.likelihood_ratio > strongest->likelihood_ratio) strongest = &f;
    }
    if (!strongest || strongest->implausible.empty()) continue;
    out << "Strongest fit" << (r.rounds.size() > 1 ? " of round " + std::to_string(k + 1) : "")
        << ": " << strongest->label << " (likelihood ratio "
        << FixedNumber(strongest->likelihood_ratio, 0)
        << "), ruled out by its size: " << strongest->implausible << ".\n";
  }
}

// The held-out figures with the accepted effects; or, where none was accepted and the mismatch
// is more than noise, that nothing passed.
void HeldOutLine(const DiagnosisResult& r, std::ostringstream& out) {
  if (!r.accepted.empty()) {
    out << "Held-out RMS " << MmWithSe(r.geometric.held_out_rms_mm, r.geometric.held_out_rms_se_mm)
        << " -> " << MmWithSe(r.final.held_out_rms_mm, r.final.held_out_rms_se_mm)
        << " (positions; gain "
        << MmWithSe(r.held_out_gain.gain_mm, r.held_out_gain.standard_error_mm)
        << (r.held_out_gain.paired ? ", paired" : "") << "), "
        << FixedNumber(r.geometric.held_out_sigma, 2) << " -> "
        << FixedNumber(r.final.held_out_sigma, 2) << " sigma (every row fitted); fit RMS "
        << Mm(r.final.rms_mm) << " against the " << Mm(r.floor_rms_mm) << " floor.\n";
  } else if (!r.geometric.consistent_with_noise()) {
    out << "No effect in the library passed every test";
    if (!r.rounds.empty() && r.rounds.front().dispersion > 1.5) {
      out << " (each judged against the residuals' own scatter, "
          << FixedNumber(r.rounds.front().dispersion, 1) << "x the floor's chi-square)";
    }
    out << ".\n";
  }
}

// The last physics round's chosen one that failed: what it would give, and why not.
void ClosestCandidates(const DiagnosisResult& r, std::ostringstream& out) {
  const DiagnosisRound* physics = LastPhysicsRound(r);
  if (!physics) return;
  for (const auto& f : physics->candidates) {
    if (f.failed.empty()) continue;
    const std::string tie = TieAtItsSite(*physics, f);
    if (!tie.empty()) out << tie << "\n";
    out << "Closest candidate: " << f.label << " (held-out RMS " << Mm(r.final.held_out_rms_mm)
        << " -> " << Mm(f.cv_rms_mm) << "), not accepted:";
    for (size_t i = 0; i < f.failed.size(); ++i)
      out << (i ? ";" : "") << " " << Why(f, f.failed[i]);
    out << ".\n";
    const std::string advice = PlanAgainstRivalAdvice(r, f);
    if (!advice.empty()) out << "  " << advice << "\n";
    if (!f.look_alikes.empty()) {
      out << "  In these poses it looks like";
      for (size_t i = 0; i < f.look_alikes.size() && i < 3; ++i) {
        out << (i ? "," : "") << " " << f.look_alikes[i].label << " ("
            << FixedNumber(f.look_alikes[i].correlation, 2) << ")";
      }
      out << " (canonical correlation of what the geometry leaves of them).\n";
    }
  }
}

// A frame the tests did not accept, and why.
void FramesNotAccepted(const DiagnosisResult& r, std::ostringstream& out) {
  for (const DiagnosisRound& round : r.rounds) {
    if (!round.frames) continue;
    for (const auto& f : round.candidates) {
      if (f.failed.empty()) continue;
      out << "Frame not accepted: " << f.label << ":";
      for (size_t i = 0; i < f.failed.size(); ++i)
        out << (i ? ";" : "") << " " << Why(f, f.failed[i]);
      out << ".\n";
    }
  }
}

}  // namespace

// The accepted effects' values in the final model, where every accepted effect is fitted
// together: each finding above gives its values as they were when it was accepted, and a later
// effect can take a share of what an earlier one absorbed. Said only where some value moved.
void FinalModelValues(const DiagnosisResult& r, std::ostringstream& out) {
  std::string values;
  bool moved = false;
  for (const AcceptedEffect& a : r.accepted) {
    for (const ScalarEstimate& at_acceptance : a.parameters) {
      for (const ScalarEstimate& s : r.final_fit.model_parameters) {
        if (s.name != at_acceptance.name) continue;
        values += (values.empty() ? "" : "; ") + Value(s);
        moved = moved || std::abs(s.value - at_acceptance.value) >
                             1e-6 * std::max(std::abs(s.value), std::abs(at_acceptance.value));
      }
    }
  }
  if (!moved) return;
  out << "Fitted together in the final model (final_fit/, what `cellmetry compensate` uses; the "
         "values above are each effect's when it was accepted): "
      << values << ".\n";
}

std::string DiagnosisReport(const DiagnosisResult& result) {
  DiagnosisResult storage;
  const DiagnosisResult& r = Grouped(result, &storage);
  std::ostringstream out;
  out << "Mismatch: " << Mm(r.geometric.rms_mm) << " RMS against a " << Mm(r.floor_rms_mm)
      << " floor (" << r.noise_source << "); chi-square/dof "
      << r.geometric.chi2 / std::max(1.0, r.geometric.dof);
  out << (r.geometric.consistent_with_noise() ? ": consistent with noise.\n" : ".\n");
  if (!r.geometric.consistent_with_noise() && !r.regressors.empty()) {
    const auto& f = r.regressors.front();
    out << "It follows " << f.regressor << " (" << f.axis << " residuals, partial correlation "
        << std::to_string(f.partial_correlation).substr(0, 5) << ").\n";
  }
  StrongestRuledOut(r, out);
  for (const auto& f : r.findings) Finding(r, f, out);
  FinalModelValues(r, out);
  HeldOutLine(r, out);
  ClosestCandidates(r, out);
  FramesNotAccepted(r, out);
  if (!r.unexplained.empty()) out << "Unexplained: " << r.unexplained << ".\n";
  if (!r.untestable.empty()) {
    out << "Not testable here:";
    for (size_t i = 0; i < r.untestable.size(); ++i) {
      const auto& u = r.untestable[i];
      out << (i ? ";" : "") << " " << u.label << " (" << u.untestable_because << "; needs "
          << u.data_needed << ")";
    }
    out << ".\n";
  }
  return out.str();
}

// Where the closest candidate passed every test but could not be told from one rival (the rival
// test's, or the one the bootstrap split the resamples with), poses planned for both (pose_plan.h:
// D-optimal for their parameters with the geometry's) are what tells them apart. Measured on
// five of the physics suite's UR3 cases at SNR 6 (ten seeds each): of the 14 runs the finder got
// wrong or left silent, 30 poses planned this way made it name the hidden effect in 9 and
// nothing wrong, 30 more random poses in 6 with one wrong name (docs/physics.md).
std::string PlanAgainstRivalAdvice(const DiagnosisResult& r, const CandidateFinding& f) {
  // Split: the candidate passes every other test, wins a material share of the resamples, and
  // the rival most others. One that fails the likelihood ratio, BIC or held-out test has no
  // evidence to split; one the resamples hardly ever choose is too weak, not contested, and
  // poses for the pair would not change that: on experiment A joint 2's gear ratio (0 % of the
  // resamples) and cam2's depth tilt are already unlike (canonical correlation 0.07), and the
  // plan for the two predicts 5 % smaller sigmas.
  // With the rival test, failing it alone is the split where the candidate still scores above
  // the rival (p < 1); a rival that scores as strongly is no contest poses for the pair settle.
  constexpr double kSplitShare = 0.2;
  const bool only_rivals = f.failed == std::vector<std::string>{"rivals"} && f.rival_p < 1.0;
  const bool only_bootstrap = f.failed == std::vector<std::string>{"bootstrap"};
  const std::string rival = only_rivals ? f.rival : f.bootstrap_rival;
  const std::string rival_effect = only_rivals ? f.rival_effect : f.bootstrap_rival_effect;
  if (!(only_rivals || (only_bootstrap && f.bootstrap_share >= kSplitShare)) ||
      rival_effect.empty()) {
    return "";
  }
  return "To tell it from " + rival + ", record the poses `cellmetry plan " +
         (r.job.empty() ? "JOB.yaml" : r.job) + " --effect " + f.name + " --effect " +
         rival_effect + "` proposes and diagnose again.";
}

std::string PlanAgainstRivalAdvice(const DiagnosisResult& r) {
  const DiagnosisRound* last = LastPhysicsRound(r);
  if (!last) return "";
  for (const auto& f : last->candidates) {
    const std::string advice = PlanAgainstRivalAdvice(r, f);
    if (!advice.empty()) return advice;
  }
  return "";
}

std::vector<std::string> TiedCandidates(const DiagnosisResult& r) {
  const DiagnosisRound* last = LastPhysicsRound(r);
  if (!last) return {};
  for (const auto& f : last->candidates) {
    if (const CandidateFinding* other = TiedRival(*last, f)) return {f.name, other->name};
  }
  return {};
}

std::string DiagnosisTie(const DiagnosisResult& r) {
  const DiagnosisRound* last = LastPhysicsRound(r);
  if (!last) return "";
  for (const auto& f : last->candidates) {
    const std::string tie = TieAtItsSite(*last, f);
    if (!tie.empty()) return tie;
  }
  return "";
}

namespace {

nlohmann::json SummaryJson(const FitSummary& s) {
  return nlohmann::json{{"chi2", s.chi2},
                        {"dof", s.dof},
                        {"p_value", s.p_value},
                        {"rms_mm", s.rms_mm},
                        {"held_out_rms_mm", s.held_out_rms_mm},
                        {"held_out_rms_se_mm", s.held_out_rms_se_mm},
                        {"held_out_sigma", s.held_out_sigma},
                        {"consistent_with_noise", s.consistent_with_noise()}};
}

nlohmann::json LookAlikesJson(const std::vector<LookAlike>& look_alikes) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& l : look_alikes) {
    out.push_back({{"label", l.label}, {"correlation", l.correlation}});
  }
  return out;
}

nlohmann::json CandidateJson(const CandidateFinding& f) {
  return nlohmann::json{{"name", f.name},
                        {"site", f.site},
                        {"label", f.label},
                        {"testable", f.testable},
                        {"untestable_because", f.untestable_because},
                        {"data_needed", f.data_needed},
                        {"unabsorbed", f.unabsorbed},
                        {"dof", f.dof},
                        {"score", f.score},
                        {"p_holm", f.p_holm},
                        {"refitted", f.refitted},
                        {"likelihood_ratio", f.likelihood_ratio},
                        {"p_lr_holm", f.p_lr_holm},
                        {"delta_bic", f.delta_bic},
                        {"cv_rms_mm", f.cv_rms_mm},
                        {"cv_gain_sigma", f.cv_gain},
                        {"cv_gain_se_sigma", f.cv_gain_se},
                        {"bootstrap_share", f.bootstrap_share},
                        {"look_alikes", LookAlikesJson(f.look_alikes)},
                        {"bootstrap_rival", f.bootstrap_rival},
                        {"bootstrap_rival_effect", f.bootstrap_rival_effect},
                        {"rival_p", f.rival_p},
                        {"rival", f.rival},
                        {"rival_effect", f.rival_effect},
                        {"aliases", f.aliases},
                        {"alias_names", f.alias_names},
                        {"implausible", f.implausible},
                        {"explained_share", f.explained_share},
                        {"failed", f.failed},
                        {"accepted", f.accepted}};
}

nlohmann::json AcceptedJson(const AcceptedEffect& a) {
  nlohmann::json j{{"name", a.name},
                   {"label", a.label},
                   {"site", a.site},
                   {"group", a.group},
                   {"group_label", a.group_label},
                   {"description", a.description},
                   {"peak_mm", a.peak_mm},
                   {"aliases", a.aliases},
                   {"look_alikes", LookAlikesJson(a.look_alikes)},
                   {"held_out_sigma_before", a.held_out_sigma_before},
                   {"held_out_sigma_after", a.held_out_sigma_after},
                   {"role", a.role},
                   {"group_share", a.group_share},
                   {"headline_correlation", a.headline_correlation},
                   {"site_correlations", a.site_correlations},
                   {"stronger_implausible", a.stronger_implausible},
                   {"frame", a.frame},
                   {"parameters", nlohmann::json::array()}};
  for (const auto& p : a.parameters) {
    j["parameters"].push_back(
        {{"name", p.name}, {"unit", p.unit}, {"value", p.value}, {"sigma", p.sigma}});
  }
  return j;
}

// One physical finding, its members by the accepted effects' names.
nlohmann::json FindingJson(const PhysicalFinding& f, const std::vector<AcceptedEffect>& accepted) {
  auto names = [&accepted](const std::vector<int>& members) {
    std::vector<std::string> out;
    for (int m : members) out.push_back(accepted[m].name);
    return out;
  };
  return {{"site", f.site},
          {"headline", accepted[f.headline].name},
          {"separate", names(f.separate)},
          {"residual_shape", names(f.residual_shape)},
          {"held_out_excess_removed", f.held_out_excess_removed}};
}

}  // namespace

nlohmann::json DiagnosisJson(const DiagnosisResult& result) {
  DiagnosisResult storage;
  const DiagnosisResult& r = Grouped(result, &storage);
  nlohmann::json j;
  j["format"] = "cellmetry-diagnosis/1";
  j["noise_source"] = r.noise_source;
  j["floor_rms_mm"] = r.floor_rms_mm;
  j["geometric"] = SummaryJson(r.geometric);
  j["final"] = SummaryJson(r.final);
  j["held_out_gain"] = {{"gain_mm", r.held_out_gain.gain_mm},
                        {"standard_error_mm", r.held_out_gain.standard_error_mm},
                        {"paired", r.held_out_gain.paired}};
  j["durbin_watson"] = r.durbin_watson;
  j["regressors"] = nlohmann::json::array();
  for (const auto& f : r.regressors) {
    j["regressors"].push_back({{"regressor", f.regressor},
                               {"axis", f.axis},
                               {"partial_correlation", f.partial_correlation},
                               {"p_value", f.p_value}});
  }
  j["untestable"] = nlohmann::json::array();
  for (const auto& f : r.untestable) j["untestable"].push_back(CandidateJson(f));
  j["rounds"] = nlohmann::json::array();
  for (const auto& round : r.rounds) {
    nlohmann::json jr{{"accepted", round.accepted},
                      {"dispersion", round.dispersion},
                      {"frames", round.frames},
                      {"candidates", nlohmann::json::array()}};
    for (const auto& f : round.candidates) jr["candidates"].push_back(CandidateJson(f));
    j["rounds"].push_back(jr);
  }
  j["tie"] = DiagnosisTie(r);
  j["accepted"] = nlohmann::json::array();
  for (const auto& a : r.accepted) j["accepted"].push_back(AcceptedJson(a));
  j["min_group_share"] = r.min_group_share;
  j["shape_correlation"] = r.shape_correlation;
  j["findings"] = nlohmann::json::array();
  for (const auto& f : r.findings) j["findings"].push_back(FindingJson(f, r.accepted));
  j["unexplained"] = r.unexplained;
  j["report"] = DiagnosisReport(r);
  return j;
}

}  // namespace cellmetry
