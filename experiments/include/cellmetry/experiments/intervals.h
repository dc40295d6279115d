// The 95 % intervals every `compare:` kind reports, and the decisions drawn from them.
//
// A comparison is repeated over seeds; a figure without its interval cannot tell a difference
// from the seed's luck. Means get a Student-t interval, rates (k of n runs right) a Wilson score
// interval; a target is met when the whole interval clears it, missed when the whole interval
// falls short, and undecided otherwise, with the number of runs that would decide it. Every
// comparison's table writes its figures and intervals the same few ways (FigureText,
// IntervalText).
#pragma once

#include <string>
#include <vector>

#include "cellmetry/basics/statistics.h"

namespace cellmetry {

// Means: MeanInterval and TInterval95 (basics/statistics.h).
bool Overlap(const MeanInterval& a, const MeanInterval& b);

// Whether two per-seed scores are the same for a decision: means within 1 % of each other or
// within `resolution` (a difference too small to matter: round-off of a noise-free fit), or
// (paired: same length, seed i of both on the same data) the 95 % t-interval of the per-seed
// differences contains 0, or (unpaired) their 95 % intervals overlap.
bool SameScore(const std::vector<double>& a, const std::vector<double>& b, double resolution = 0.0);

// A rate (k of n) and its 95 % Wilson score interval (E. B. Wilson, "Probable inference, the
// law of succession, and statistical inference", JASA 22, 1927, eq. for p with z = 1.96). Unlike
// the normal approximation it stays inside [0, 1] and is not empty at k = 0 or k = n: 5 of 5 is
// [0.57, 1], not a certainty.
struct RateInterval {
  int k = 0;
  int n = 0;
  double rate = 0.0;  // k / n (NaN when n = 0)
  double low = 0.0;
  double high = 1.0;
};
RateInterval WilsonInterval95(int k, int n);

enum class TargetVerdict { kMet, kMissed, kUndecided };

// Met: the interval's low end is at or above `target`; missed: its high end is below it;
// undecided otherwise (and with n = 0).
TargetVerdict AgainstTarget(const RateInterval& r, double target);

// The fewest runs, all right, whose Wilson interval clears `target` (< 1): how many runs a case
// needs before "at least 90 %" can be shown at all (35 for 90 %, 73 for 95 %).
int RunsToShowAtLeast(double target);

// The runs that would decide an undecided rate: the fewest n > `runs_so_far` whose Wilson
// interval at the same rate lies wholly on one side of `target`; -1 when none up to a million
// does (the rate is at the target).
int RunsToDecide(double rate, double target, int runs_so_far);

// "87 % [81 %, 92 %] (109/125)".
std::string RateText(const RateInterval& r);

// How a comparison's table writes a figure.
enum class FigureStyle {
  kThreeDigits,   // 3 significant digits ("0.0123", "152"); "1.23e-05" below 1e-3 (not 0)
  kFourDecimals,  // 4 decimals ("12.3457"); "1.2e-05" below 1e-3 (not 0)
  kFourDigits,    // 4 significant digits ("12.35", "0.0001235")
};
std::string FigureText(double value, FigureStyle style = FigureStyle::kThreeDigits);

// "1.23 [1.1, 1.36]": a mean and its 95 % interval, each times `scale` (1e3: seconds as ms) and
// written as FigureText.
std::string IntervalText(const MeanInterval& m, double scale = 1.0,
                         FigureStyle style = FigureStyle::kThreeDigits);
// The same for TInterval95(values); "-" for no values.
std::string IntervalText(const std::vector<double>& values, double scale = 1.0,
                         FigureStyle style = FigureStyle::kThreeDigits);

}  // namespace cellmetry
