// The regressors the physics finder correlates residuals with (core/diagnosis/src/
// diagnosis_regressors.h), on a recording of times alone: the order of capture, the time, steps
// at each tenth of the run, and a step across a pause the samples' times show.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "cellmetry/formats/recording.h"
#include "diagnosis_regressors.h"

namespace cellmetry {
namespace {

using ::testing::Contains;
using ::testing::Not;

// `n` samples 7.5 s apart, with `pause_s` more before sample `resume` (0: none).
Recording Captures(int n, int resume, double pause_s) {
  Recording r;
  double t = 0.0;
  for (int i = 0; i < n; ++i) {
    Sample s;
    s.id = i;
    s.time_s = t;
    r.samples.push_back(s);
    t += 7.5 + (i + 1 == resume ? pause_s : 0.0);
  }
  return r;
}

std::vector<std::string> Names(const Recording& recording) {
  const std::vector<SampleFacts> facts(recording.samples.size());
  std::vector<std::string> names;
  for (const Regressor& r : SampleRegressors(recording, facts, {}, Eigen::Vector3d(0, 0, -9.81))) {
    names.push_back(r.name);
  }
  return names;
}

TEST(DiagnosisRegressors, AStepAcrossAPauseIsOfferedWithItsLengthAndWhereItFell) {
  // 300 captures, the last 19 an hour and 41 minutes later (the held-out TX90L recording's).
  const Recording r = Captures(300, 281, 6095.0);
  const std::vector<std::string> names = Names(r);
  EXPECT_THAT(names, Contains("a step across the 1.7 h pause after capture 280"));
  EXPECT_THAT(names, Contains("a step after capture 270"));  // the tenths stay
  const std::vector<SampleFacts> facts(r.samples.size());
  for (const Regressor& reg : SampleRegressors(r, facts, {}, Eigen::Vector3d(0, 0, -9.81))) {
    if (reg.name.find("pause") == std::string::npos) continue;
    EXPECT_EQ(reg.per_sample[280], 0.0);
    EXPECT_EQ(reg.per_sample[281], 1.0);
    EXPECT_EQ(std::count(reg.per_sample.begin(), reg.per_sample.end(), 1.0), 19);
  }
}

TEST(DiagnosisRegressors, NoPauseWhereTheIntervalsAreEvenOrTheLongestIsShort) {
  for (const auto& name : Names(Captures(100, 0, 0.0))) {
    EXPECT_EQ(name.find("pause"), std::string::npos) << name;
  }
  // 50 s more than the usual 7.5 s is ten times the median but not a minute.
  EXPECT_THAT(Names(Captures(100, 40, 50.0)), Not(Contains(::testing::HasSubstr("pause"))));
  EXPECT_THAT(Names(Captures(100, 40, 600.0)),
              Contains("a step across the 10 min pause after capture 39"));
}

}  // namespace
}  // namespace cellmetry
