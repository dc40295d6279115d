// Progress reports on stderr (progress.h): a line at most every 0.5 s with the rate and the time
// left at that rate, and one at the end, all behind one process-wide quiet switch for tests and
// benchmarks.
#include "cellmetry/basics/progress.h"

#include <atomic>
#include <cstdio>

namespace cellmetry {
namespace {
std::atomic<bool> g_quiet{false};
std::atomic<bool> g_verbose{false};
std::atomic<int> g_running{0};  // reports alive now, in any thread
}  // namespace

Progress::Progress(std::string task, int total)
    : task_(std::move(task)), total_(total), outermost_(g_running.fetch_add(1) == 0),
      start_(std::chrono::steady_clock::now()), last_print_(start_) {}

Progress::~Progress() {
  if (done_ > 0 && done_ != total_) Print(true);  // left early: say where it stopped
  g_running.fetch_sub(1);
}

void Progress::Resume(int steps) {
  resumed_ += steps;
  done_ += steps;
  if (!g_quiet && (outermost_ || g_verbose)) {
    std::fprintf(stderr, "cellmetry: %s %d/%d resumed (finished before)\n", task_.c_str(), done_,
                 total_);
  }
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
  if (g_quiet || (!outermost_ && !g_verbose)) return;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const int worked = done_ - resumed_;
  if (final || worked <= 0 || seconds <= 0.0) {
    const char* end = !final ? "" : done_ == total_ ? " done" : " stopped";
    std::fprintf(stderr, "cellmetry: %s %d/%d (%.1f s)%s\n", task_.c_str(), done_, total_,
                 seconds, end);
    return;
  }
  // The rate of this run's steps, and the time left at that rate.
  const double rate = worked / seconds;
  std::fprintf(stderr, "cellmetry: %s %d/%d (%.1f s, %.3g/s, about %.0f s left)\n",
               task_.c_str(), done_, total_, seconds, rate, (total_ - done_) / rate);
}

void Progress::SetQuiet(bool quiet) { g_quiet = quiet; }
bool Progress::quiet() { return g_quiet; }
void Progress::SetVerbose(bool verbose) { g_verbose = verbose; }

void Progress::Note(const std::string& text) {
  if (g_quiet || (g_running > 0 && !g_verbose)) return;
  std::fprintf(stderr, "cellmetry: %s\n", text.c_str());
}

}  // namespace cellmetry
