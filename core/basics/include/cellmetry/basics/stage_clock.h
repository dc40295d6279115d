// StageClock: the wall time and memory of a pipeline's stages, in the order they ran.
//
// A pipeline (IdentifyWorkcell, for one) laps the clock as each stage ends; the result keeps the
// laps, so a user sees where the time of a long run went and the scale benchmark reports time
// and memory per stage from the same figures.
//
// Memory is the process's peak resident set so far (the kernel's VmHWM), read at each lap: it
// only grows, and the stage whose lap raised it is the one that needed the memory. Reading it
// costs one small file read; nothing is reset.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace cellmetry {

struct StageTime {
  std::string stage;              // a short identifier: "solve", "covariance", ...
  double seconds = 0.0;           // wall time of the stage
  double peak_resident_mb = 0.0;  // process peak resident memory at the stage's end (0: unknown)
  int pass = 0;                   // 0 the first identification; 1 the one again without the
                                  // outliers the first found (workcell.cc)
};

class StageClock {
 public:
  StageClock();  // the first stage starts now

  // Ends the stage that ran since the last lap (or since construction) and names it.
  void Lap(const std::string& stage);
  const std::vector<StageTime>& stages() const { return stages_; }

 private:
  std::chrono::steady_clock::time_point last_;
  std::vector<StageTime> stages_;
};

// The process's peak resident memory in MB (getrusage's ru_maxrss, VmHWM); 0 where unknown.
double PeakResidentMb();

}  // namespace cellmetry
