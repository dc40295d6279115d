// Progress: a one-line progress report on stderr for work that takes more than a second.
//
// Prints "cellmetry: <task> k/n (t s)" at most every 0.5 s (and at the end), so logs stay short
// and a person watching a terminal sees the work move. Quiet() silences all progress (tests,
// benchmarks).
#pragma once

#include <chrono>
#include <string>

namespace cellmetry {

class Progress {
 public:
  Progress(std::string task, int total);
  ~Progress();
  void Advance(int steps = 1);

  static void SetQuiet(bool quiet);
  static bool quiet();
  // A one-off status line ("cellmetry: solving with ceres_lm").
  static void Note(const std::string& text);

 private:
  void Print(bool final);

  std::string task_;
  int total_;
  int done_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
};

}  // namespace cellmetry
