// Progress reports on stderr (progress.h): a line at most every 0.5 s with the rate and the time
// left at that rate, and one at the end, all behind one process-wide quiet switch for tests and
// benchmarks.
#include "cellmetry/basics/progress.h"

#include <atomic>
#include <cstdio>

namespace cellmetry {
namespace {
std::atomic<bool> g_quiet{false};
}

Progress::Progress(std::string task, int total)
    : task_(std::move(task)), total_(total), start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

Progress::~Progress() {
  if (done_ > 0 && done_ != total_) Print(true);  // interrupted early: say where it stopped
}

void Progress::Advance(int steps) {
  done_ += steps;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_print_ > std::chrono::milliseconds(500) || done_ == total_) {
    last_print_ = now;
    Print(done_ == total_);
  }
}

void Progress::Print(bool final) {
  if (g_quiet) return;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (final || done_ == 0 || seconds <= 0.0) {
    std::fprintf(stderr, "cellmetry: %s %d/%d (%.1f s)%s\n", task_.c_str(), done_, total_,
                 seconds, final ? " done" : "");
    return;
  }
  // The rate so far, and the time left at that rate.
  const double rate = done_ / seconds;
  std::fprintf(stderr, "cellmetry: %s %d/%d (%.1f s, %.3g/s, about %.0f s left)\n",
               task_.c_str(), done_, total_, seconds, rate, (total_ - done_) / rate);
}

void Progress::SetQuiet(bool quiet) { g_quiet = quiet; }
bool Progress::quiet() { return g_quiet; }

void Progress::Note(const std::string& text) {
  if (!g_quiet) std::fprintf(stderr, "cellmetry: %s\n", text.c_str());
}

}  // namespace cellmetry
