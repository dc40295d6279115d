// Progress reports (basics/progress.h): the outermost report speaks, nested work and notes made
// meanwhile are detail shown only with --verbose, and resumed steps stay out of the time left.
#include <gtest/gtest.h>

#include <string>

#include "cellmetry/basics/progress.h"

namespace cellmetry {
namespace {

int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

std::string RunNestedWork() {
  ::testing::internal::CaptureStderr();
  {
    Progress outer("seeds", 2);
    for (int seed = 0; seed < 2; ++seed) {
      Progress inner("folds", 3);
      Progress::Note("fitting 12 target observations");
      for (int fold = 0; fold < 3; ++fold) inner.Advance();
      outer.Advance();
    }
  }
  return ::testing::internal::GetCapturedStderr();
}

TEST(Progress, NestedWorkAndItsNotesAreDetail) {
  Progress::SetQuiet(false);
  const std::string plain = RunNestedWork();
  EXPECT_EQ(Count(plain, "seeds 2/2"), 1) << plain;
  EXPECT_EQ(Count(plain, "folds"), 0) << plain;
  EXPECT_EQ(Count(plain, "fitting"), 0) << plain;

  Progress::SetVerbose(true);
  const std::string verbose = RunNestedWork();
  Progress::SetVerbose(false);
  EXPECT_EQ(Count(verbose, "folds 3/3"), 2) << verbose;
  EXPECT_EQ(Count(verbose, "fitting 12 target observations"), 2) << verbose;

  ::testing::internal::CaptureStderr();
  Progress::Note("alone");  // no report running: a note is the news
  EXPECT_EQ(Count(::testing::internal::GetCapturedStderr(), "alone"), 1);
  Progress::SetQuiet(true);
}

TEST(Progress, ResumedStepsAreSaidAndLeftOutOfTheRate) {
  Progress::SetQuiet(false);
  ::testing::internal::CaptureStderr();
  {
    Progress progress("cases", 4);
    progress.Resume(2);
  }
  const std::string text = ::testing::internal::GetCapturedStderr();
  Progress::SetQuiet(true);
  EXPECT_NE(text.find("cases 2/4 resumed"), std::string::npos) << text;
  // Stopped with nothing run: where it stopped, without a rate made of resumed steps.
  EXPECT_EQ(text.find("/s,"), std::string::npos) << text;
  EXPECT_NE(text.find("cases 2/4 (0.0 s) stopped"), std::string::npos) << text;
}

// A diagnosis's shape: steps said as they begin, the total the most the work can take until it
// stops sooner, and the time left said as at most.
TEST(Progress, WorkThatMayStopSoonerSaysItsStepsAndAnUpperBound) {
  Progress::SetQuiet(false);
  ::testing::internal::CaptureStderr();
  {
    Progress rounds("round", 5, Progress::Length::kAtMost);
    rounds.Begin("scoring 70 candidates");
    rounds.Advance();
    rounds.Begin("scoring 54 candidates");
    rounds.Advance();
    rounds.SetTotal(2);  // the second round accepted nothing
  }
  const std::string text = ::testing::internal::GetCapturedStderr();
  Progress::SetQuiet(true);
  EXPECT_NE(text.find("round 0 of at most 5: scoring 70 candidates (0.0 s)\n"), std::string::npos)
      << text;
  EXPECT_NE(text.find("round 1 of at most 5: scoring 54 candidates ("), std::string::npos) << text;
  EXPECT_NE(text.find("at most about"), std::string::npos) << text;
  EXPECT_EQ(Count(text, "round 2/2"), 1) << text;  // the last line, once, not "stopped"
  EXPECT_EQ(Count(text, "done"), 1) << text;
  EXPECT_EQ(Count(text, "\n"), 3) << text;  // a line a step as it begins, and the end
}

TEST(Progress, ResumedWorkThatMayStopSoonerSaysItsUpperBound) {
  Progress::SetQuiet(false);
  ::testing::internal::CaptureStderr();
  {
    Progress rounds("round", 5, Progress::Length::kAtMost);
    rounds.Resume(2);
    rounds.SetTotal(2);
  }
  const std::string text = ::testing::internal::GetCapturedStderr();
  Progress::SetQuiet(true);
  EXPECT_NE(text.find("round 2 of at most 5 resumed (finished before)"), std::string::npos) << text;
}

}  // namespace
}  // namespace cellmetry
