// Bad input to the delta arm's calibration and homing, through the real command line: one error
// line naming the file, the line and what to do, exit code 2, no result folder left behind.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

using ::testing::HasSubstr;
using testing::ReadText;
using testing::ReplaceOnce;

// A simulated 40-position recording of the nominal delta arm, and jobs on it, in a temp folder.
class DeltaBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDirForThisTest("delta_cli");
    robot_ = dir_ + "/delta.yaml";
    recording_ = dir_ + "/rec";
    output_ = dir_ + "/result";
    fs::copy_file(testing::Source("configs/robots/delta.yaml"), robot_);
    testing::WriteText(dir_ + "/sim.yaml",
                       "simulation: workcell\n"
                       "world_target: none\n"
                       "robots:\n"
                       "  delta:\n"
                       "    model: " +
                           robot_ +
                           "\n"
                           "    errors: {dimensions_mm: 1.0, homing_increments: 5}\n"
                           "    tools: {marker: {measures: position}}\n"
                           "    poses: {set: uniform_workspace, count: 40}\n"
                           "cameras:\n"
                           "  stereo: {xyz: [0, 250, -150], rvec: [3.0, 0, 0],\n"
                           "           errors: {mm: 1.0, rad: 0.01}}\n"
                           "noise: {position_mm: [0.013, 0.012, 0.058]}\n");
    const auto sim = testing::RunCellmetry("simulate " + dir_ + "/sim.yaml -o " + recording_);
    ASSERT_EQ(sim.exit_code, 0) << sim.output;
  }

  // The delta's calibration as the one pipeline's job: one robot, its model free, one camera.
  std::string CalibrationJob(const std::string& residual) const {
    return "job: workcell\n"
           "recording: " +
           recording_ +
           "\n"
           "output: " +
           output_ +
           "\n"
           "world_target: none\n"
           "robots:\n"
           "  delta: {model: " +
           robot_ +
           ", free_model: [all], tools: {marker: {free: none}}}\n"
           "cameras: {stereo: {free: all}}\n"
           "residual: " +
           residual +
           "\n"
           "validation: {folds: 0}\n"
           "solver: {type: ceres_lm}\n";
  }

  testing::CommandResult Run(const std::string& command, const std::string& job_text) {
    testing::WriteText(dir_ + "/job.yaml", job_text);
    return testing::RunCellmetry(command + " " + dir_ + "/job.yaml");
  }

  // Keeps the first `rows` data rows of a recording file.
  void Truncate(const std::string& file, int rows) {
    std::istringstream in(ReadText(recording_ + "/" + file));
    std::string text, line;
    for (int n = 0; std::getline(in, line) && n <= rows; ++n) text += line + "\n";
    testing::WriteText(recording_ + "/" + file, text);
  }

  void ExpectRejected(const testing::CommandResult& r, const std::string& location,
                      const std::string& message) {
    testing::ExpectOneLineError(r, location, message);
    EXPECT_FALSE(fs::exists(output_)) << "a result folder was written";
  }

  std::string dir_, robot_, recording_, output_;
};

TEST_F(DeltaBadInput, TheUnmodifiedJobRuns) {
  const auto r = Run("run", CalibrationJob("joint_space"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(output_ + "/result.yaml"));
}

TEST_F(DeltaBadInput, UnreachableCommand) {
  testing::EditLine(recording_ + "/samples.csv", 5, "3,delta,3,2.5,0.1,0.1");
  ExpectRejected(Run("run", CalibrationJob("cartesian")), "samples.csv:5:4:",
                 "unreachable command: q1 = 2.5000 rad is outside the joint limits");
}

TEST_F(DeltaBadInput, CommandWhereTheRodSpheresDoNotMeet) {
  // A config whose rods (300 mm) are shorter than the elbows' spread: the recorded commands have
  // no pose under it.
  testing::WriteText(
      robot_,
      ReplaceOnce(ReadText(robot_),
                  "arms:\n  - {R: 150, r: 40, L: 250, l: 600, homing: 0}\n  - {R: 150, r: 40, L: "
                  "250, l: 600, homing: 0}\n  - {R: 150, r: 40, L: 250, l: 600, homing: 0}",
                  "arms:\n  - {R: 150, r: 40, L: 250, l: 300}\n  - {R: 150, r: 40, L: 250, l: "
                  "300}\n  - {R: 150, r: 40, L: 250, l: 300}"));
  ExpectRejected(Run("run", CalibrationJob("cartesian")),
                 "samples.csv:2:", "the three rod spheres do not meet");
}

TEST_F(DeltaBadInput, MeasuredPointOutOfReach) {
  // With the outlier test on the plain fit only, the point 5 m off reaches the joint-space
  // assembly, which names its line. (By default the robust first fit finds it first: below.)
  testing::EditLine(recording_ + "/observations.csv", 4, "2,stereo,marker,0,0,5000,,,");
  ExpectRejected(
      Run("run", CalibrationJob("joint_space") + "outliers: plain\n"),
      "observations.csv:4:", "the measured point is out of the arm's reach: arm 1 cannot reach");
}

TEST_F(DeltaBadInput, MeasuredPointOutOfReachIsAnOutlierByDefault) {
  testing::EditLine(recording_ + "/observations.csv", 4, "2,stereo,marker,0,0,5000,,,");
  const auto r = Run("run", CalibrationJob("joint_space"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(ReadText(output_ + "/outliers.csv").substr(0, 53),
            "line,sample,camera,target,kind,score,threshold\n4,2,st");
}

TEST_F(DeltaBadInput, FewerMeasuredValuesThanFreeParameters) {
  Truncate("samples.csv", 6);
  Truncate("observations.csv", 6);
  ExpectRejected(Run("run", CalibrationJob("cartesian")), "observations.csv:",
                 "the recording gives 18 measured values for 21 free parameters");
}

TEST_F(DeltaBadInput, TheOldKinematicJobSaysHowToWriteItNow) {
  ExpectRejected(Run("run", "job: kinematic\nrecording: " + recording_ + "\n"),
                 "job.yaml:1:6:", "'job: kinematic' is now a workcell job");
}

TEST_F(DeltaBadInput, HomingWithTooFewPositions) {
  Truncate("samples.csv", 2);
  Truncate("observations.csv", 2);
  const std::string job =
      "job: homing\n"
      "recording: " +
      recording_ +
      "\n"
      "output: " +
      output_ +
      "\n"
      "world_target: none\n"
      "robots: {delta: {model: " +
      robot_ +
      ", tools: {marker: }}}\n"
      "cameras: {stereo: {xyz: [0, 250, -150], rvec: [3.0, 0, 0]}}\n"
      "noise: {cameras: {stereo: {position_mm: [0.013, 0.012, 0.058]}}}\n";
  ExpectRejected(Run("home", job),
                 "samples.csv:", "homing needs at least 3 measured positions, the recording has 2");
}

TEST_F(DeltaBadInput, CompareWritesTheTable) {
  testing::WriteText(dir_ + "/compare.yaml",
                     "compare: kinematic\n"
                     "simulation: " +
                         dir_ +
                         "/sim.yaml\n"
                         "pose_sets: [camera_view, boundaries]\n"
                         "sizes: [24]\n"
                         "formulations: [inverse, forward]\n"
                         "solvers: {lm: {type: ceres_lm}}\n"
                         "validation_points: 50\n"
                         "output: " +
                         output_ + "\n");
  const auto r = testing::RunCellmetry("compare " + dir_ + "/compare.yaml");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string csv = ReadText(output_ + "/table.csv");
  EXPECT_THAT(csv, HasSubstr("camera_view,24,inverse,lm,"));
  EXPECT_THAT(csv, HasSubstr("boundaries,24,forward,lm,"));
  EXPECT_THAT(ReadText(output_ + "/table.md"), HasSubstr("floor RMS"));
}

}  // namespace
}  // namespace cellmetry
