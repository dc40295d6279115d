#include "cellmetry/basics/stage_clock.h"

#include <cstdlib>
#include <fstream>

namespace cellmetry {

StageClock::StageClock() : last_(std::chrono::steady_clock::now()) {}

void StageClock::Lap(const std::string& stage) {
  const auto now = std::chrono::steady_clock::now();
  stages_.push_back({stage, std::chrono::duration<double>(now - last_).count(), PeakResidentMb()});
  last_ = now;
}

double PeakResidentMb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;  // kB
  }
  return 0.0;
}

}  // namespace cellmetry
