// The physics suite's results as markdown: rates with 95 % intervals and verdicts, one decision
// line per question, the cases, and each cell's confusion matrix (physics_suite.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "cellmetry/basics/statistics.h"
#include "cellmetry/experiments/intervals.h"
#include "cellmetry/experiments/physics_suite.h"
#include "cellmetry/formats/fixed_number.h"

namespace cellmetry {
namespace {

constexpr double kNamedTarget = 0.90;  // the bar: the right effect named in >= 90 % of runs
constexpr double kCleanTarget = 0.95;  // clean recordings: no claim in >= 95 %
constexpr double kFloorTarget = 1.2;   // held-out RMS at most 1.2x the noise floor

std::string Percent(double rate) { return FixedNumber(100.0 * rate, 0) + " %"; }

// The suite's runs in three groups, and the held-out ratios and times of the effect cases.
struct SuiteTally {
  int effect_runs = 0, effect_right = 0, effect_wrong = 0;  // wrong: another effect named
  int effect_silent = 0, effect_tied = 0;  // nothing named; of those, tied with it at its site
  int richer_runs = 0, richer_right = 0, richer_wrong = 0;  // of them, physics concealed
  int clean_runs = 0, clean_right = 0;
  int outside_runs = 0, outside_right = 0;
  std::vector<double> held_out_over_floor, seconds;
};

// A silent run whose report ties the hidden effect with a rival at its joint or camera.
bool TiedWithIt(const SuiteCaseResult& r, const SuiteRun& run) {
  return std::any_of(run.tied.begin(), run.tied.end(),
                     [&](const std::string& t) { return t.rfind(r.spec.expect, 0) == 0; });
}

SuiteTally Tally(const std::vector<SuiteCaseResult>& results) {
  SuiteTally t;
  for (const auto& r : results) {
    const int right = r.right();
    const int n = static_cast<int>(r.runs.size());
    if (r.spec.expect == "none") {
      t.clean_runs += n, t.clean_right += right;
    } else if (r.spec.expect == "unexplained") {
      t.outside_runs += n, t.outside_right += right;
    } else {
      t.effect_runs += n, t.effect_right += right;
      for (const auto& run : r.runs) {
        const bool claimed = run.named != "none" && run.named != "unexplained";
        t.effect_wrong += claimed && !r.named_right(run);
        if (r.spec.concealed) {
          ++t.richer_runs;
          t.richer_right += r.named_right(run);
          t.richer_wrong += claimed && !r.named_right(run);
        }
        if (!claimed && !r.named_right(run)) {
          ++t.effect_silent;
          t.effect_tied += TiedWithIt(r, run);
        }
        t.held_out_over_floor.push_back(run.held_out_over_floor);
      }
    }
    for (const auto& run : r.runs) t.seconds.push_back(run.seconds);
  }
  return t;
}

// The oracle's best guess over the effect cases with draws, each case weighted equally (each
// has the same runs): "97 % right, 3.0 % wrong, over 25 cases".
std::string OracleSummary(const std::vector<SuiteCaseResult>& results) {
  int cases = 0;
  double right = 0.0;
  for (const auto& r : results) {
    if (r.oracle.draws() == 0) continue;
    ++cases;
    right += r.oracle.right_share();
  }
  if (cases == 0) return "-";
  right /= cases;
  return Percent(right) + " right, " + FixedNumber(100.0 * (1.0 - right), 1) + " % wrong, over " +
         std::to_string(cases) + " cases";
}

std::string VerdictWord(TargetVerdict v) {
  return v == TargetVerdict::kMet ? "met" : v == TargetVerdict::kMissed ? "missed" : "undecided";
}

// "<question> <verdict>: 87 % [81 %, 92 %] (109/125) against >= 90 %; <what would decide>".
std::string RateDecision(const std::string& question, int k, int n, double target) {
  const RateInterval r = WilsonInterval95(k, n);
  if (n == 0) return question + " not asked (no such cases)";
  const TargetVerdict verdict = AgainstTarget(r, target);
  std::string line =
      question + " " + VerdictWord(verdict) + ": " + RateText(r) + " against >= " + Percent(target);
  if (verdict != TargetVerdict::kUndecided) return line;
  if (k == n) {
    return line + "; no run failed, and " + std::to_string(RunsToShowAtLeast(target)) +
           " runs without a failure would show the target met";
  }
  const int runs = RunsToDecide(r.rate, target, n);
  return line + (runs < 0 ? "; the rate sits at the target: more runs will not decide it"
                          : "; at this rate about " + std::to_string(runs) +
                                " runs would decide it (" + std::to_string(n) + " so far)");
}

// "all of them" as a target: any miss misses it; none in n runs is as far as runs can show.
std::string AllDecision(const std::string& question, int k, int n) {
  if (n == 0) return question + " not asked (no such cases)";
  const RateInterval r = WilsonInterval95(k, n);
  if (k < n) return question + " missed: " + RateText(r) + " against all";
  return question + " so far: " + RateText(r) + ", no miss";
}

std::string FloorDecision(const std::vector<double>& ratios) {
  const MeanInterval m = TInterval95(ratios);
  const std::string figures = FixedNumber(m.mean, 2) + " [" + FixedNumber(m.low, 2) + ", " +
                              FixedNumber(m.high, 2) + "] (mean of " + std::to_string(m.n) +
                              " runs) against <= " + FixedNumber(kFloorTarget, 1);
  const std::string question = "Does the accepted model bring the held-out RMS to the floor?";
  if (m.n < 2) return question + " undecided: fewer than two runs";
  if (m.high <= kFloorTarget) return question + " met: " + figures;
  if (m.low > kFloorTarget) return question + " missed: " + figures;
  return question + " undecided: " + figures;
}

// Per cell: the cases shown below 90 % (their whole interval under it) and what was named.
std::string WeakCases(const std::string& cell, const std::vector<SuiteCaseResult>& results,
                      double snr) {
  std::string weak;
  int undecided = 0, met = 0;
  for (const auto& r : results) {
    if (r.cell != cell || r.spec.expect == "none" || r.spec.expect == "unexplained") continue;
    const RateInterval rate = WilsonInterval95(r.right(), static_cast<int>(r.runs.size()));
    const TargetVerdict verdict = AgainstTarget(rate, kNamedTarget);
    met += verdict == TargetVerdict::kMet;
    undecided += verdict == TargetVerdict::kUndecided;
    if (verdict != TargetVerdict::kMissed) continue;
    std::map<std::string, int> instead;
    int tied_right = 0;  // silent, but tied at the hidden effect's site with it among the two
    for (const auto& run : r.runs) {
      if (r.named_right(run)) continue;
      ++instead[run.named];
      tied_right += TiedWithIt(r, run);
    }
    std::string named;
    for (const auto& [name, count] : instead) {
      named += (named.empty() ? "" : ", ") + name + " " + std::to_string(count);
    }
    if (tied_right > 0) {
      named += "; " + std::to_string(tied_right) + " of them tied with it at its site";
    }
    weak += (weak.empty() ? "" : "; ") + r.spec.name + " " + std::to_string(rate.k) + "/" +
            std::to_string(rate.n) + " (named instead: " + named + ")";
  }
  std::string line = cell + " at SNR " + FixedNumber(snr, 1) + ": ";
  line += weak.empty() ? "no case shown below " + Percent(kNamedTarget)
                       : "shown below " + Percent(kNamedTarget) +
                             ", do not trust a silence or "
                             "these names: " +
                             weak;
  line += "; " + std::to_string(met) + " shown at or above, " + std::to_string(undecided) +
          " undecided";
  return line;
}

// Rows: the cell's cases; columns: what the finder named first.
std::string ConfusionMatrix(const std::string& cell, const std::vector<SuiteCaseResult>& results) {
  std::set<std::string> named_set;
  for (const auto& r : results) {
    if (r.cell != cell) continue;
    for (const auto& run : r.runs) named_set.insert(run.named);
  }
  std::ostringstream out;
  out << "\n"
      << cell << " confusion matrix (rows: expected; columns: what the finder named first):\n\n| |";
  const std::vector<std::string> named(named_set.begin(), named_set.end());
  for (const auto& n : named) out << " " << n << " |";
  out << "\n|---|";
  for (size_t i = 0; i < named.size(); ++i) out << "---|";
  out << "\n";
  for (const auto& r : results) {
    if (r.cell != cell) continue;
    std::map<std::string, int> counts;
    for (const auto& run : r.runs) ++counts[run.named];
    out << "| " << r.spec.name << " |";
    for (const auto& n : named) {
      out << " " << (counts.count(n) ? std::to_string(counts[n]) : "") << " |";
    }
    out << "\n";
  }
  return out.str();
}

std::string CaseRow(const SuiteCaseResult& r) {
  std::vector<double> ratios;
  for (const auto& run : r.runs) ratios.push_back(run.held_out_over_floor);
  char size[32];
  std::snprintf(size, sizeof(size), "%.3g", r.magnitude);
  std::string misses;
  for (const auto& run : r.runs) {
    if (!run.failed.empty() && !r.named_right(run)) {
      misses += (misses.empty() ? "" : "; ") + run.failed;
    }
  }
  const RateInterval rate = WilsonInterval95(r.right(), static_cast<int>(r.runs.size()));
  const std::string oracle = r.oracle.draws() > 0 ? Percent(r.oracle.right_share()) + " (" +
                                                        FixedNumber(r.oracle.mismatch_norm, 1) + ")"
                                                  : "-";
  return "| " + r.cell + " | " + r.spec.name + " | " + r.spec.expect + " | " + size + " | " +
         std::to_string(rate.k) + "/" + std::to_string(rate.n) + " [" + Percent(rate.low) + ", " +
         Percent(rate.high) + "] | " + oracle + " | " + FixedNumber(Median(ratios), 2) + " | " +
         misses + " |\n";
}

}  // namespace

std::vector<std::string> PhysicsSuiteRecommendations(const PhysicsSuiteSpec& spec,
                                                     const std::vector<SuiteCaseResult>& results) {
  const SuiteTally t = Tally(results);
  std::vector<std::string> lines = {
      RateDecision("Is the right effect named?", t.effect_right, t.effect_runs, kNamedTarget),
      RateDecision("Are the richer variants named?", t.richer_right, t.richer_runs, kNamedTarget),
      RateDecision("Do clean recordings stay clean?", t.clean_right, t.clean_runs, kCleanTarget),
      AllDecision("Is physics outside the library called unexplained?", t.outside_right,
                  t.outside_runs),
      FloorDecision(t.held_out_over_floor)};
  for (const auto& cell : spec.cells) lines.push_back(WeakCases(cell.name, results, spec.snr));
  return lines;
}

std::string PhysicsSuiteMarkdown(const PhysicsSuiteSpec& spec,
                                 const std::vector<SuiteCaseResult>& results) {
  const SuiteTally t = Tally(results);
  auto rate = [](int k, int n) { return RateText(WilsonInterval95(k, n)); };
  auto verdict = [](int k, int n, double target) {
    return VerdictWord(AgainstTarget(WilsonInterval95(k, n), target));
  };
  const MeanInterval floor = TInterval95(t.held_out_over_floor);
  std::ostringstream out;
  out << "Concealed-effect suite: " << spec.seeds << " seeds per case, unabsorbed SNR "
      << FixedNumber(spec.snr, 1)
      << ". Rates with their 95 % Wilson interval; a target is met when "
      << "the whole interval clears it, missed when the whole interval falls short.\n\n";
  out << "| measure | result [95 % interval] | target | verdict |\n|---|---|---|---|\n";
  out << "| right effect named (library and richer variants) | "
      << rate(t.effect_right, t.effect_runs) << " | >= 90 % | "
      << verdict(t.effect_right, t.effect_runs, kNamedTarget) << " |\n";
  out << "| of them, richer variants (physics not in the library's equations): named; wrong | "
      << rate(t.richer_right, t.richer_runs) << "; " << t.richer_wrong << "/" << t.richer_runs
      << " | >= 90 %; none | " << verdict(t.richer_right, t.richer_runs, kNamedTarget) << "; "
      << (t.richer_wrong == 0 ? "met" : "missed") << " |\n";
  out << "| the oracle's best guess on each case's poses, always naming one (oracle_selection.h) | "
      << OracleSummary(results) << " | | |\n";
  out << "| silent, but the hidden effect tied with a rival at its joint or camera (the report "
         "names both) | "
      << t.effect_tied << " of " << t.effect_silent << " silent runs | | |\n";
  out << "| wrong effect named | " << t.effect_wrong << "/" << t.effect_runs << " | none | "
      << (t.effect_wrong == 0 ? "met" : "missed") << " |\n";
  out << "| no effect claimed on clean recordings | " << rate(t.clean_right, t.clean_runs)
      << " | >= 95 % | " << verdict(t.clean_right, t.clean_runs, kCleanTarget) << " |\n";
  out << "| outside the library reported as unexplained | " << rate(t.outside_right, t.outside_runs)
      << " | all | "
      << (t.outside_runs == 0                ? "-"
          : t.outside_right < t.outside_runs ? "missed"
                                             : "no miss")
      << " |\n";
  out << "| held-out RMS / noise floor after modelling: median; mean [95 % t] | "
      << FixedNumber(Median(t.held_out_over_floor), 2) << "; " << FixedNumber(floor.mean, 2) << " ["
      << FixedNumber(floor.low, 2) << ", " << FixedNumber(floor.high, 2) << "] | <= 1.2 | "
      << (floor.high <= kFloorTarget ? "met"
          : floor.low > kFloorTarget ? "missed"
                                     : "undecided")
      << " |\n";
  out << "| seconds per diagnosis (median) | " << FixedNumber(Median(t.seconds), 1) << " | | |\n\n";
  out << "Decisions:\n\n";
  for (const auto& line : PhysicsSuiteRecommendations(spec, results)) out << "- " << line << "\n";
  out << "\n| cell | case | expected | effect size | right [95 %] | "
         "oracle's best guess right (SNR it sees) | held-out / floor (median) | "
         "misses: best candidate and the tests it failed |\n"
         "|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : results) out << CaseRow(r);
  for (const auto& cell : spec.cells) out << ConfusionMatrix(cell.name, results);
  return out.str();
}

}  // namespace cellmetry
