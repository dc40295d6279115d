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
#pragma once

#include <chrono>
#include <string>

namespace cellmetry {

class Progress {
 public:
  Progress(std::string task, int total);
  ~Progress();
  void Advance(int steps = 1);
  // Steps finished before (read from a checkpoint): done, and left out of the rate.
  void Resume(int steps);

  static void SetQuiet(bool quiet);
  static bool quiet();
  static void SetVerbose(bool verbose);
  // A one-off status line ("cellmetry: solving with ceres_lm"); detail while a report runs.
  static void Note(const std::string& text);

 private:
  void Print(bool final);

  std::string task_;
  int total_;
  int done_ = 0;
  int resumed_ = 0;
  bool outermost_ = true;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
};

}  // namespace cellmetry
