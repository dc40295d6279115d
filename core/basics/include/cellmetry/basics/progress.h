// Progress: a one-line progress report on stderr for work that takes more than a second.
//
// Prints "cellmetry: <task> k/n (t s, rate, about T s left)" at most every 0.5 s (and at the
// end), so logs stay short and a person watching a terminal sees the work move. Quiet() silences
// all progress (tests, benchmarks).
//
// Only the outermost report speaks: work nested inside another's steps (a fit's
// cross-validation inside a comparison's seeds) and the notes made meanwhile are detail, shown
// with SetVerbose(true) (`cellmetry --verbose`). Steps resumed from a checkpoint count as done
// but not in the rate, so the time left is the work's, not the checkpoint's.
//
// Work whose length its data decide (a diagnosis, whose rounds end when no candidate passes)
// is made with Length::kAtMost: the total is the most it can take, the time left is said as at
// most that, and SetTotal lowers the total once the work knows it stops sooner. Few long steps
// say what each does as it starts (Begin), whatever the 0.5 s limit.
#pragma once

#include <chrono>
#include <string>

namespace cellmetry {

class Progress {
 public:
  enum class Length { kExact, kAtMost };

  Progress(std::string task, int total, Length length = Length::kExact);
  ~Progress();
  void Advance(int steps = 1);
  // Says the step starting now: "<task> k/n: <what> (t s, about T s left)", k the steps done.
  void Begin(const std::string& what);
  // The total as the work now knows it (kAtMost: no more than it was); the last line when the
  // steps done reach it.
  void SetTotal(int total);
  // Steps finished before (read from a checkpoint): done, and left out of the rate.
  void Resume(int steps);

  static void SetQuiet(bool quiet);
  static bool quiet();
  static void SetVerbose(bool verbose);
  // A one-off status line ("cellmetry: solving with ceres_lm"); detail while a report runs.
  static void Note(const std::string& text);

 private:
  void Print(bool final, const std::string& what = "");

  std::string task_;
  int total_;
  Length length_;
  int done_ = 0;
  int resumed_ = 0;
  bool outermost_ = true;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
  std::chrono::steady_clock::time_point step_start_;  // the last step's end: the next's start
  double resumed_seconds_ = 0.0;                      // spent reading resumed steps back
  bool begun_ = false;                                // steps said by Begin
};

}  // namespace cellmetry
