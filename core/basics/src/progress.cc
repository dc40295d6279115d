// Progress reports on stderr (progress.h): a line at most every 0.5 s with the rate and the time
// left at that rate, and one at the end, all behind one process-wide quiet switch for tests and
// benchmarks.
#include "cellmetry/basics/progress.h"

#include <algorithm>
#include <atomic>
#include <cstdio>

namespace cellmetry {
namespace {
std::atomic<bool> g_quiet{false};
std::atomic<bool> g_verbose{false};
std::atomic<int> g_running{0};  // reports alive now, in any thread
}  // namespace

Progress::Progress(std::string task, int total, Length length)
    : task_(std::move(task)), total_(total), length_(length),
      outermost_(g_running.fetch_add(1) == 0), start_(std::chrono::steady_clock::now()),
      last_print_(start_), step_start_(start_) {}

Progress::~Progress() {
  if (done_ > 0 && done_ != total_) Print(true);  // left early: say where it stopped
  g_running.fetch_sub(1);
}

void Progress::Resume(int steps) {
  resumed_ += steps;
  done_ += steps;
  const auto now = std::chrono::steady_clock::now();
  resumed_seconds_ += std::chrono::duration<double>(now - step_start_).count();
  step_start_ = now;
  if (!g_quiet && (outermost_ || g_verbose)) {
    std::fprintf(stderr, "cellmetry: %s %d%s%d resumed (finished before)\n", task_.c_str(), done_,
                 length_ == Length::kAtMost ? " of at most " : "/", total_);
  }
}

void Progress::Advance(int steps) {
  done_ += steps;
  const auto now = std::chrono::steady_clock::now();
  step_start_ = now;
  // Steps that say themselves as they begin need no line as they end, but the last.
  if ((!begun_ && now - last_print_ > std::chrono::milliseconds(500)) || done_ == total_) {
    last_print_ = now;
    Print(done_ == total_);
  }
}

void Progress::Begin(const std::string& what) {
  begun_ = true;
  last_print_ = std::chrono::steady_clock::now();
  Print(false, what);
}

void Progress::SetTotal(int total) {
  if (total == total_) return;
  total_ = total;
  if (done_ >= total_) Print(true);
}

void Progress::Print(bool final, const std::string& what) {
  if (g_quiet || (!outermost_ && !g_verbose)) return;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const int worked = done_ - resumed_;
  const bool at_most = length_ == Length::kAtMost && !final;
  // "3/10", or "3 of at most 10" while the work may stop sooner.
  const std::string count = std::to_string(done_) + (at_most ? " of at most " : "/") +
                            std::to_string(total_) + (what.empty() ? "" : ": " + what);
  if (final || worked <= 0 || seconds <= 0.0) {
    const char* end = !final ? "" : done_ >= total_ ? " done" : " stopped";
    std::fprintf(stderr, "cellmetry: %s %s (%.1f s)%s\n", task_.c_str(), count.c_str(), seconds,
                 end);
    return;
  }
  // The rate of this run's steps (the time reading resumed ones back left out), and the time
  // left at that rate.
  const double rate = worked / std::max(seconds - resumed_seconds_, 1e-9);
  std::fprintf(stderr, "cellmetry: %s %s (%.1f s, %.3g/s, %sabout %.0f s left)\n", task_.c_str(),
               count.c_str(), seconds, rate, at_most ? "at most " : "", (total_ - done_) / rate);
}

void Progress::SetQuiet(bool quiet) { g_quiet = quiet; }
bool Progress::quiet() { return g_quiet; }
void Progress::SetVerbose(bool verbose) { g_verbose = verbose; }

void Progress::Note(const std::string& text) {
  if (g_quiet || (g_running > 0 && !g_verbose)) return;
  std::fprintf(stderr, "cellmetry: %s\n", text.c_str());
}

}  // namespace cellmetry
