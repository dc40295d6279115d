// Bad input through the real command line: every case gets one error line naming the file, the
// line and what to do, exit code 2, and no result folder (not even a partial one).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

#include "cellmetry/formats/recording.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

using testing::ReadText;

// configs/jobs/vsb_sim_b.yaml with absolute paths; line numbers matter to the tests.
std::string SimBJobText(const std::string& recording, const std::string& output,
                        const std::string& robot) {
  return "job: workcell\n"                                   // 1
         "description: UR3 base + tool offset, VSB sim B\n"  // 2
         "recording: " +
         recording +
         "\n"  // 3
         "output: " +
         output +
         "\n"                              // 4
         "camera_model: static_cameras\n"  // 5
         "robots:\n"                       // 6
         "  ur3:\n"                        // 7
         "    model: " +
         robot +
         "\n"                                               // 8
         "    base: {free: all}\n"                          // 9
         "    tools:\n"                                     // 10
         "      tool: {xyz: [0, 0, 0], free: [x, y, z]}\n"  // 11
         "solver:\n"                                        // 12
         "  type: ceres_lm\n"                               // 13
         "validation:\n"                                    // 14
         "  folds: 5\n";                                    // 15
}

// The unmodified job's result folder, made once per test process: `export`, `evaluate` and
// `compensate` only read it, and making it is a whole identification with cross-validation,
// ~10 s a time under the sanitizers for the 13 tests that need one. Its result.json names the
// robot config it was made with, which stays in the maker's folder (one per process: ctest runs
// tests side by side, each in its own process).
const std::string& SharedSimBResult() {
  static const std::string result = [] {
    const std::string dir =
        testing::TempDir("bad_input/shared_result_" + std::to_string(::getpid()));
    fs::copy(testing::Source("tests/data/vsb/sim_b"), dir + "/sim_b");
    fs::copy_file(testing::Source("configs/robots/ur3_vsb2020.yaml"), dir + "/ur3.yaml");
    testing::WriteText(dir + "/job.yaml",
                       SimBJobText(dir + "/sim_b", dir + "/result", dir + "/ur3.yaml"));
    const auto run = testing::RunCellmetry("run " + dir + "/job.yaml");
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return dir + "/result";
  }();
  return result;
}
using testing::ReplaceOnce;

// A copy of the sim_b job, recording and UR3 config in a temp folder, to be broken one way.
class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDirForThisTest("bad_input");
    recording_ = dir_ + "/sim_b";
    robot_ = dir_ + "/ur3.yaml";
    output_ = dir_ + "/result";
    job_ = dir_ + "/job.yaml";
    fs::copy(testing::Source("tests/data/vsb/sim_b"), recording_);
    fs::copy_file(testing::Source("configs/robots/ur3_vsb2020.yaml"), robot_);
  }

  std::string JobText() const { return SimBJobText(recording_, output_, robot_); }

  void WriteJob(const std::string& text) { testing::WriteText(job_, text); }
  void WriteJob() { WriteJob(JobText()); }

  // Replaces line `line` (1-based) of a recording file.
  void EditLine(const std::string& file, int line, const std::string& replacement) {
    testing::EditLine(recording_ + "/" + file, line, replacement);
  }

  testing::CommandResult Run() { return testing::RunCellmetry("run " + job_); }

  // The unmodified job's result where the job would write it (a copy of the shared one).
  void CopyInTheJobsResult() {
    ASSERT_TRUE(fs::exists(SharedSimBResult() + "/result.json"));
    fs::copy(SharedSimBResult(), output_, fs::copy_options::recursive);
  }

  // The contract for every bad input: exit 2, one line "<location> error: ... <hint>", and
  // nothing left behind.
  void ExpectRejected(const testing::CommandResult& r, const std::string& location,
                      const std::string& hint) {
    testing::ExpectOneLineError(r, location, hint);
    EXPECT_FALSE(fs::exists(output_)) << "a result folder was written";
    for (const auto& entry : fs::recursive_directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_EQ(name.find(".partial"), std::string::npos) << entry.path();
      EXPECT_EQ(name.find(".tmp"), std::string::npos) << entry.path();
    }
  }

  std::string dir_, recording_, robot_, output_, job_;
};

TEST_F(BadInput, UnmodifiedJobRunsAndWritesItsResult) {
  WriteJob();
  const auto r = Run();
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(output_ + "/result.yaml"));
  EXPECT_TRUE(fs::exists(output_ + "/result.json"));
  EXPECT_TRUE(fs::exists(output_ + "/residuals.csv"));
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
  }
}

TEST_F(BadInput, UnknownKeyInTheJobSuggestsTheKnownOne) {
  WriteJob(ReplaceOnce(JobText(), "solver:\n", "solvr:\n"));
  const auto r = Run();
  ExpectRejected(r, "job.yaml:12:1:", "Did you mean 'solver'?");
  EXPECT_THAT(r.output, HasSubstr("solvr: unknown key"));
}

TEST_F(BadInput, WrongTypeNamesTheKeyPath) {
  WriteJob(ReplaceOnce(JobText(), "folds: 5", "folds: many"));
  const auto r = Run();
  ExpectRejected(r, "job.yaml:15:10:", "Write a whole number");
  EXPECT_THAT(r.output, HasSubstr("validation.folds: expected a whole number, got 'many'"));
}

TEST_F(BadInput, MissingRecordingFolderPointsAtTheJobLine) {
  WriteJob(ReplaceOnce(JobText(), "recording: " + recording_, "recording: " + dir_ + "/nowhere"));
  const auto r = Run();
  ExpectRejected(r, "job.yaml:3:12:", "Point 'recording:' at a cellmetry-recording/1 folder");
  EXPECT_THAT(r.output, HasSubstr("no recording at '" + dir_ + "/nowhere'"));
}

TEST_F(BadInput, ToolWithoutSettingsTakesTheDefaults) {
  // Not bad input: `tool:` with no value frees the tool position, starting at the flange.
  WriteJob(ReplaceOnce(JobText(), "tool: {xyz: [0, 0, 0], free: [x, y, z]}", "tool:"));
  const auto r = Run();
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(ReadText(output_ + "/result.yaml"), HasSubstr("tool:"));
}

TEST_F(BadInput, ToolTargetNotInTheRecordingPointsAtTheJobLine) {
  WriteJob(ReplaceOnce(JobText(), "      tool: {", "      gripper: {"));
  const auto r = Run();
  ExpectRejected(r, "job.yaml:11:16:", "List under 'tools:' the targets recording.yaml puts");
  EXPECT_THAT(r.output, HasSubstr("target 'gripper' is not carried by robot 'ur3'"));
}

TEST_F(BadInput, MissingRobotConfigPointsAtTheJobLine) {
  WriteJob(ReplaceOnce(JobText(), "model: " + robot_, "model: " + dir_ + "/ur5.yaml"));
  const auto r = Run();
  ExpectRejected(r, "job.yaml:8:12:", "Give a path relative to the job file");
  EXPECT_THAT(r.output, HasSubstr(dir_ + "/ur5.yaml"));
}

// Found by fuzz_job: a name longer than the file system allows threw std::filesystem_error
// (exit 1, "internal error") instead of saying the file is not there.
TEST_F(BadInput, RobotConfigNameTooLongForTheFileSystem) {
  WriteJob(
      ReplaceOnce(JobText(), "model: " + robot_, "model: " + std::string(5000, 'x') + ".yaml"));
  ExpectRejected(Run(), "job.yaml:8:12:", "Give a path relative to the job file");
}

// Found by fuzz_job in CI: the same for a validation recording's folder name.
TEST_F(BadInput, ValidationRecordingNameTooLongForTheFileSystem) {
  WriteJob(ReplaceOnce(
      JobText(), "output: ", "validation_recording: " + std::string(5000, 's') + "\noutput: "));
  ExpectRejected(Run(), "job.yaml:4:23:", "relative to the job file");
}

TEST_F(BadInput, SamplesWithoutThePoseColumn) {
  WriteJob();
  std::istringstream in(ReadText(recording_ + "/samples.csv"));
  std::string text;
  for (std::string line; std::getline(in, line);) {
    // Drop the third cell of every row.
    const size_t second = line.find(',', line.find(',') + 1);
    const size_t third = line.find(',', second + 1);
    text += line.substr(0, second) + line.substr(third) + "\n";
  }
  testing::WriteText(recording_ + "/samples.csv", text);
  const auto r = Run();
  ExpectRejected(r, "samples.csv:1:", "The header must name it");
  EXPECT_THAT(r.output, HasSubstr("missing column 'pose'"));
}

// One broken line of a recording file, and the error it must produce.
struct LineEdit {
  std::string name;
  std::string file;
  int line;
  std::string replacement;
  std::string location;  // file:line:column of the bad cell
  std::string hint;
  std::string message;
};

class BadRecordingLine : public BadInput, public ::testing::WithParamInterface<LineEdit> {};

TEST_P(BadRecordingLine, IsRejectedAtItsCell) {
  const LineEdit& edit = GetParam();
  WriteJob();
  EditLine(edit.file, edit.line, edit.replacement);
  const auto r = Run();
  ExpectRejected(r, edit.location, edit.hint);
  EXPECT_THAT(r.output, HasSubstr(edit.message));
}

INSTANTIATE_TEST_SUITE_P(
    Recording, BadRecordingLine,
    ::testing::Values(
        LineEdit{"NonNumericJointValue", "samples.csv", 5,
                 "3,ur3,3,4.700736523,3.39327383,abc,4.095294476,5.03745842,0.69",
                 "samples.csv:5:6:", "Write a plain decimal number",
                 "column 'q3': 'abc' is not a number"},
        LineEdit{"HexadecimalJointValue", "samples.csv", 5,
                 "3,ur3,3,4.700736523,3.39327383,0x1p8,4.095294476,5.03745842,0.69",
                 "samples.csv:5:6:", "Write a plain decimal number",
                 "column 'q3': '0x1p8' is not a number"},
        LineEdit{
            "JointValueWithANulByte", "samples.csv", 5,
            std::string("3,ur3,3,4.700736523,3.39327383,2\0 42.29,4.095294476,5.03745842,0.69", 66),
            "samples.csv:5:6:", "Write a plain decimal number",
            "column 'q3': '2\\x00 42.29' is not a number"},
        LineEdit{"JointValueBeyondRange", "samples.csv", 5,
                 "3,ur3,3,4.700736523,3.39327383,1e400,4.095294476,5.03745842,0.69",
                 "samples.csv:5:6:", "Write the value in the file's units",
                 "column 'q3': '1e400' is beyond the range of a number"},
        LineEdit{"OverlongJointValueIsQuotedShort", "samples.csv", 5,
                 "3,ur3,3,4.700736523,3.39327383,0." + std::string(5000, '7') +
                     "x,4.095294476,5.03745842,0.69",
                 "samples.csv:5:6:", "Write a plain decimal number",
                 "column 'q3': '0." + std::string(78, '7') + "...' is not a number"},
        LineEdit{"JointValueWithAUnit", "samples.csv", 5,
                 "3,ur3,3,4.700736523,3.39327383,42.29deg,4.095294476,5.03745842,0.69",
                 "samples.csv:5:6:", "Write a plain decimal number",
                 "column 'q3': '42.29deg' is not a number"},
        LineEdit{"OverlongCameraNameIsQuotedShort", "observations.csv", 4,
                 "1," + std::string(5000, 'c') +
                     ",tool,244.702809,-55.417908,725.561068,-2.15,1.60,0.53",
                 "observations.csv:4:2:", "List it under 'cameras' in recording.yaml",
                 "unknown camera '" + std::string(80, 'c') + "...'"},
        LineEdit{"NanJointValue", "samples.csv", 5,
                 "3,ur3,3,4.700736523,nan,0.7314307094,4.095294476,5.03745842,0.69",
                 "samples.csv:5:5:", "replace the value with a measurement",
                 "column 'q2': 'nan' is not a finite number"},
        LineEdit{"SampleWithTooFewJoints", "samples.csv", 5,
                 "3,ur3,3,4.700736523,3.39327383,0.7314307094,4.095294476,5.03745842",
                 "samples.csv:5:9:", "Give one joint value per joint",
                 "robot 'ur3' has 6 joints but this sample has no q6"},
        // Sample 3 said to repeat pose 2 (sample 2's, line 4) though its joints moved on.
        LineEdit{"PoseIdThatContradictsTheJoints", "samples.csv", 5,
                 "3,ur3,2,4.700736523,3.39327383,0.7314307094,4.095294476,5.03745842,0.69",
                 "samples.csv:5:3:",
                 "Give each commanded pose its own pose id; captures of one pose share it",
                 "sample 3 repeats pose 2 of sample 2 (line 4), but its q1 differs by 0.0144 rad"},
        // The joints and rotations are radians: read as degrees the flange hardly turns.
        LineEdit{"AnglesInRadiansDeclaredAsDegrees", "recording.yaml", 3,
                 "units: {length: mm, angle: deg}", "recording.yaml:3:28:",
                 "The recording's angles look like radians: declare units: {angle: rad} there",
                 "robot ur3 turns its flange unlike target 'tool' turns in cam1 between "
                 "captures (their angles and axes, median): 56 % apart with the recording's "
                 "angles in deg, 0.1 % read in rad"},
        LineEdit{"ObservationOfAnUnknownCamera", "observations.csv", 4,
                 "1,cam9,tool,244.702809,-55.417908,725.561068,-2.15,1.60,0.53",
                 "observations.csv:4:2:", "List it under 'cameras' in recording.yaml",
                 "unknown camera 'cam9'"},
        LineEdit{"ObservationOfAnUnknownTarget", "observations.csv", 4,
                 "1,cam1,tool2,244.702809,-55.417908,725.561068,-2.15,1.60,0.53",
                 "observations.csv:4:3:", "List it under 'targets' in recording.yaml",
                 "unknown target 'tool2'"},
        LineEdit{"HugePositionOfAnObservation", "observations.csv", 4,
                 "1,cam1,tool,1e300,-55.417908,725.561068,-2.15,1.60,0.53", "observations.csv:4:4:",
                 "check the units declared in recording.yaml", "is beyond any measurement of it"},
        LineEdit{"HugeRotationOfAnObservation", "observations.csv", 4,
                 "1,cam1,tool,244.702809,-55.417908,725.561068,-2.15,1e300,0.53",
                 "observations.csv:4:8:", "check the units declared in recording.yaml",
                 "is beyond any measurement of it"},
        LineEdit{"HugeJointReading", "samples.csv", 5,
                 "3,ur3,3,4.700736523,3.39327383,1e17,4.095294476,5.03745842,0.69",
                 "samples.csv:5:6:", "check the units declared in recording.yaml",
                 "is beyond any measurement of it"},
        LineEdit{"ObservationOfAnUnknownSample", "observations.csv", 4,
                 "999,cam1,tool,244.702809,-55.417908,725.561068,-2.15,1.60,0.53",
                 "observations.csv:4:1:", "name a sample listed in samples.csv",
                 "unknown sample 999"},
        // Was a hang: samples.csv's column names q1..qN were made from the count (found by review,
        // reproduced by fuzz_recording: a timeout).
        LineEdit{"HugeJointCount", "recording.yaml", 5, "  ur3: {joints: 2000000000}",
                 "recording.yaml:5:17:", "Give the robot's number of joints",
                 "joint count must be between 1 and 64"}),
    [](const ::testing::TestParamInfo<LineEdit>& info) { return info.param.name; });

TEST_F(BadInput, RecordingWithNoUsableObservation) {
  // Only the world target was seen: nothing ties the robot to the cameras.
  WriteJob();
  std::istringstream in(ReadText(recording_ + "/observations.csv"));
  std::string text;
  for (std::string line; std::getline(in, line);) {
    if (line.find(",tool,") == std::string::npos) text += line + "\n";
  }
  testing::WriteText(recording_ + "/observations.csv", text);
  const auto r = Run();
  // A whole-file problem: no single line is to blame.
  ExpectRejected(r, "observations.csv:", "observations name them");
  EXPECT_THAT(r.output, HasSubstr("no usable observation of a robot-carried target"));
}

TEST_F(BadInput, UnknownSolverTypeListsTheKnownOnes) {
  WriteJob(ReplaceOnce(JobText(), "type: ceres_lm", "type: ceres_lmm"));
  const auto r = Run();
  ExpectRejected(r, "job.yaml:13:9:", "Did you mean 'ceres_lm'?");
  EXPECT_THAT(r.output, HasSubstr("unknown solver type 'ceres_lmm'"));
  EXPECT_THAT(r.output,
              HasSubstr("Known solver types: ceres_lm, gradient_descent, jacobian_pinv, nlopt"));
}

TEST_F(BadInput, UnknownRobotModelTypeListsTheKnownOnes) {
  WriteJob();
  testing::WriteText(robot_,
                     ReplaceOnce(ReadText(robot_), "type: serial_mdh", "type: serial_mdhh"));
  const auto r = Run();
  ExpectRejected(r, "ur3.yaml:4:7:", "Did you mean 'serial_mdh'?");
  EXPECT_THAT(r.output, HasSubstr("unknown robot model type 'serial_mdhh'"));
  EXPECT_THAT(r.output, HasSubstr("Known robot model types: delta, serial_mdh, urdf"));
}

// A job value outside its meaning: `from` in the job text becomes `to` (or `to` is appended when
// `from` is empty), and the run is rejected at the value, with the message and what to do.
struct JobEdit {
  std::string name;
  std::string from, to;
  std::string location;  // file:line: of the bad value
  std::string hint;
  std::string message;
};

class BadJobValue : public BadInput, public ::testing::WithParamInterface<JobEdit> {};

TEST_P(BadJobValue, IsRejectedAtItsValue) {
  const JobEdit& edit = GetParam();
  WriteJob(edit.from.empty() ? JobText() + edit.to : ReplaceOnce(JobText(), edit.from, edit.to));
  const auto r = Run();
  ExpectRejected(r, edit.location, edit.hint);
  EXPECT_THAT(r.output, HasSubstr(edit.message));
}

INSTANTIATE_TEST_SUITE_P(
    Job, BadJobValue,
    ::testing::Values(
        JobEdit{"NegativeFolds", "folds: 5", "folds: -3", "job.yaml:15:10:",
                "0 turns cross-validation off", "validation.folds: must be between 0 and 1000"},
        JobEdit{"OneFold", "folds: 5", "folds: 1",
                "job.yaml:15:10:", "0 turns cross-validation off", "one fold holds nothing out"},
        JobEdit{"ZeroSigma", "", "noise: {cameras: {cam1: {position_mm: [0, 0.1, 0.4]}}}\n",
                "job.yaml:16:39:", "give the measurement's real scatter",
                "every entry must be positive"},
        JobEdit{"NegativeRotationSigma", "",
                "noise: {cameras: {cam1: {rotation_rad: [0.001, -0.001, 0.001]}}}\n",
                "job.yaml:16:40:", "give the measurement's real scatter",
                "every entry must be positive"},
        JobEdit{"NegativeFloor", "", "noise: {floor_mm: -1}\n", "job.yaml:16:19:",
                "the smallest sigma any camera gets", "noise.floor_mm: must be between 0 and"},
        JobEdit{"NoiseForACameraTheRecordingLacks", "",
                "noise: {cameras: {cam9: {position_mm: [0.1, 0.1, 0.4]}}}\n",
                "job.yaml:16:25:", "Name the cameras as recording.yaml does",
                "camera 'cam9' under noise: is not in the recording"},
        JobEdit{"NegativeIdentifiabilityTolerance", "", "identifiability_tolerance: -1\n",
                "job.yaml:16:28:", "1e-8 is the default",
                "identifiability_tolerance: must be between"},
        JobEdit{"VifBelowOne", "", "weak_vif: 0.5\n", "job.yaml:16:11:", "at least 1",
                "weak_vif: must be between 1 and"},
        JobEdit{"MissingPluginFolder", "", "plugin_paths: [/nonexistent/cellmetry/plugins]\n",
                "job.yaml:16:16:", "Point plugin_paths at the folder",
                "no plugin folder at '/nonexistent/cellmetry/plugins'"},
        JobEdit{"DuplicateKey", "", "validation:\n  folds: 3\n",
                "job.yaml:16:1:", "Keep one of them", "key 'validation' appears twice in this map"},
        JobEdit{"ToolNameOfAnotherRobot", "solver:\n",
                "  ur3b:\n    model: ur3.yaml\n    base: {free: all}\n    tools:\n"
                "      tool:\nsolver:\n",
                "job.yaml:16:7:", "give each robot's tool its own name",
                "robots.ur3b.tools: target 'tool' is already a tool of robot 'ur3'"},
        // Was undefined behaviour (UBSan, scripts/sanitize.sh): -1 held in an nlopt_algorithm.
        JobEdit{"UnknownNloptAlgorithm", "type: ceres_lm", "type: nlopt\n  algorithm: LD_LBFGSS",
                "job.yaml:14:14:", "Use an NLopt name such as LD_LBFGS",
                "unknown NLopt algorithm 'LD_LBFGSS'"}),
    [](const ::testing::TestParamInfo<JobEdit>& info) { return info.param.name; });

// The command table: every option of every command, and values of the job, the robot config,
// the recording and the simulation spec, given outside their meaning. Each row edits one file
// of BadInput's copy (or none) and runs one command; it must exit 2 with a message that names
// the file and line (or the option) and says what to do, and leave every file in the test's
// folder as it was, byte for byte (the output folder included: none is written).

// Every file and folder under `dir`, with the files' bytes.
std::map<std::string, std::string> Snapshot(const std::string& dir) {
  std::map<std::string, std::string> out;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string path = entry.path().string();
    out[path] = entry.is_regular_file() ? ReadText(path) : std::string("<folder>");
  }
  return out;
}

// The first path whose presence or bytes differ ("" when none does).
std::string FirstDifference(const std::map<std::string, std::string>& before,
                            const std::map<std::string, std::string>& after) {
  for (const auto& [path, bytes] : before) {
    const auto it = after.find(path);
    if (it == after.end()) return path + " was removed";
    if (it->second != bytes) return path + " was changed";
  }
  for (const auto& [path, bytes] : after) {
    if (!before.count(path)) return path + " was created";
  }
  return "";
}

// A billion-laughs YAML: 9 levels of 9 aliases name one list 9^9 (387 million) times in 10
// lines. Appended to a file as top-level keys it is read before any key is checked.
const char kAliasBomb[] =
    "a0: &a0 [x, x, x, x, x, x, x, x, x]\n"
    "a1: &a1 [*a0, *a0, *a0, *a0, *a0, *a0, *a0, *a0, *a0]\n"
    "a2: &a2 [*a1, *a1, *a1, *a1, *a1, *a1, *a1, *a1, *a1]\n"
    "a3: &a3 [*a2, *a2, *a2, *a2, *a2, *a2, *a2, *a2, *a2]\n"
    "a4: &a4 [*a3, *a3, *a3, *a3, *a3, *a3, *a3, *a3, *a3]\n"
    "a5: &a5 [*a4, *a4, *a4, *a4, *a4, *a4, *a4, *a4, *a4]\n"
    "a6: &a6 [*a5, *a5, *a5, *a5, *a5, *a5, *a5, *a5, *a5]\n"
    "a7: &a7 [*a6, *a6, *a6, *a6, *a6, *a6, *a6, *a6, *a6]\n"
    "a8: &a8 [*a7, *a7, *a7, *a7, *a7, *a7, *a7, *a7, *a7]\n"
    "a9: &a9 [*a8, *a8, *a8, *a8, *a8, *a8, *a8, *a8, *a8]\n";

// How the refusal reads: "<location> error: <message>. <hint>" on one line (InputError), or
// CLI11's usage error (the option and its rule, then "Run with --help for more information.").
enum class Said { kOneLine, kUsage };

struct BadCase {
  std::string name;
  std::string file;  // edited, relative to the test's folder ("": none)
  int line;          // > 0: that line of `file` becomes `to`
  std::string from;  // else `from` becomes `to` ("": `to` appended; "*": the whole file)
  std::string to;
  std::string command;  // {dir}: the test's folder; {job}: its job.yaml; {result}: the
                        // unmodified job's result (CopyInTheJobsResult); {src}: configs/
  int exit_code;
  Said said;
  std::string location;  // kOneLine: what precedes " error: " (file:line:column:, an option)
  std::string message;   // what is wrong, as printed ({dir} expanded)
  std::string hint;      // what to do, as printed
};

class BadCommand : public BadInput, public ::testing::WithParamInterface<BadCase> {
 protected:
  std::string Expand(std::string text) const {
    for (const auto& [key, value] : {std::pair<std::string, std::string>{"{job}", job_},
                                     {"{result}", output_},
                                     {"{dir}", dir_},
                                     {"{src}", testing::Source("configs")}}) {
      for (size_t at = text.find(key); at != std::string::npos; at = text.find(key, at)) {
        text.replace(at, key.size(), value);
        at += value.size();
      }
    }
    return text;
  }

  // The job, a simulation spec and the files the command-line rows name (and the job's result
  // where the row's command reads one), then the row's edit.
  void Prepare(const BadCase& c) {
    WriteJob();
    if (c.command.find("{result}") != std::string::npos) CopyInTheJobsResult();
    testing::WriteText(
        dir_ + "/sim.yaml",
        ReplaceOnce(ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml")),
                    "../robots/ur3_vsb2020.yaml", robot_));
    testing::WriteText(dir_ + "/notes.txt", "mine\n");
    testing::WriteText(dir_ + "/empty.yaml", "");
    testing::WriteText(dir_ + "/cmp.yaml", "compare: everything\n");
    testing::WriteText(dir_ + "/map.yaml", "mapping: cellmetry-import/1\n");
    if (c.file.empty()) return;
    const std::string path = dir_ + "/" + c.file;
    const std::string to = Expand(c.to);
    if (c.line > 0) {
      testing::EditLine(path, c.line, to);
    } else if (c.from == "*") {
      testing::WriteText(path, to);
    } else {
      const std::string text = ReadText(path);
      testing::WriteText(path, c.from.empty() ? text + to : ReplaceOnce(text, c.from, to));
    }
  }
};

TEST_P(BadCommand, IsRefusedSayingWhereAndWhatToDoAndTouchesNothing) {
  const BadCase& c = GetParam();
  Prepare(c);
  const auto before = Snapshot(dir_);
  const auto r = testing::RunCellmetry(Expand(c.command));
  EXPECT_EQ(r.exit_code, c.exit_code) << r.output;
  if (c.said == Said::kOneLine) {
    testing::ExpectOneLineError(r, c.location, Expand(c.hint));
  } else {
    EXPECT_THAT(r.output, HasSubstr(Expand(c.hint)));
  }
  EXPECT_THAT(r.output, HasSubstr(Expand(c.message)));
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
  EXPECT_EQ(FirstDifference(before, Snapshot(dir_)), "");
}

const std::vector<BadCase> kBadCases = {
    {"TooManyFolds", "job.yaml", 0, "folds: 5", "folds: 1001", "run {job}", 2, Said::kOneLine,
     "job.yaml:15:10:", "validation.folds: must be between 0 and 1000",
     "0 turns cross-validation off; 5 is usual"},
    {"FractionalFolds", "job.yaml", 0, "folds: 5", "folds: 2.5", "run {job}", 2, Said::kOneLine,
     "job.yaml:15:10:", "validation.folds: expected a whole number, got '2.5'",
     "Write a whole number"},
    {"NegativeSeed", "job.yaml", 0, "folds: 5", "folds: 5\n  seed: -1", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:9:", "validation.seed: must be between 0 and 2147483647",
     "A seed is a whole number, 0 or more"},
    {"CompareCameraModelsNotABool", "job.yaml", 0, "folds: 5",
     "folds: 5\n  compare_camera_models: maybe", "run {job}", 2, Said::kOneLine,
     "job.yaml:16:26:", "validation.compare_camera_models: expected true or false, got 'maybe'",
     "Write true or false"},
    {"UnknownCameraModel", "job.yaml", 0, "camera_model: static_cameras", "camera_model: fisheye",
     "run {job}", 2, Said::kOneLine, "job.yaml:5:15:",
     "camera_model: unknown camera model 'fisheye'", "Use static_cameras or per_frame"},
    {"UnknownResidual", "job.yaml", 0, "", "residual: polar\n", "run {job}", 2, Said::kOneLine,
     "job.yaml:16:11:", "residual: unknown residual 'polar'", "Use cartesian or joint_space"},
    {"JointSpaceResidualWithoutInverseKinematics", "job.yaml", 0, "", "residual: joint_space\n",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:16:11:", "residual: the joint-space residual needs position inverse kinematics,",
     "Use residual: cartesian"},
    {"UseToolRotationNotABool", "job.yaml", 0, "", "use_tool_rotation: sometimes\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:20:",
     "use_tool_rotation: expected true or false, got 'sometimes'", "Write true or false"},
    {"WorldTargetNotInTheRecording", "job.yaml", 0, "", "world_target: floor\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:15:", "the recording has no world-fixed target 'floor'",
     "to a target that recording.yaml puts 'on: world'"},
    {"IdentifiabilityToleranceOne", "job.yaml", 0, "", "identifiability_tolerance: 1\n",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:16:28:", "identifiability_tolerance: must be between 1e-16 and 0.1",
     "A relative singular value: 1e-8 is the default"},
    {"IdentifiabilityToleranceNan", "job.yaml", 0, "", "identifiability_tolerance: .nan\n",
     "run {job}", 2, Said::kOneLine, "job.yaml:16:28:",
     "identifiability_tolerance: expected a finite number, got '.nan'", "Write a finite number"},
    {"WeakVifInfinite", "job.yaml", 0, "", "weak_vif: .inf\n", "run {job}", 2, Said::kOneLine,
     "job.yaml:16:11:", "weak_vif: expected a finite number, got '.inf'", "Write a finite number"},
    {"FloorNan", "job.yaml", 0, "", "noise: {floor_mm: .nan}\n", "run {job}", 2, Said::kOneLine,
     "job.yaml:16:19:", "noise.floor_mm: expected a finite number, got '.nan'",
     "Write a finite number"},
    {"NegativeRotationFloor", "job.yaml", 0, "", "noise: {floor_rad: -1}\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:20:", "noise.floor_rad: must be between 0 and 1",
     "A floor is the smallest sigma any camera gets, in rad"},
    {"PositionSigmaOfTwoEntries", "job.yaml", 0, "",
     "noise: {cameras: {cam1: {position_mm: [0.1, 0.1]}}}\n", "run {job}", 2, Said::kOneLine,
     "job.yaml:16:39:", "noise.cameras.cam1.position_mm: expected a list of 3 numbers, got 2",
     "Give 3 numbers in brackets"},
    {"PositionSigmaAWord", "job.yaml", 0, "", "noise: {cameras: {cam1: {position_mm: abc}}}\n",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:16:39:", "noise.cameras.cam1.position_mm: expected a list, got 'abc'",
     "Write a list in brackets: [a, b, c]"},
    {"RotationSigmaInfinite", "job.yaml", 0, "",
     "noise: {cameras: {cam1: {rotation_rad: [.inf, 0.001, 0.001]}}}\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:41:",
     "noise.cameras.cam1.rotation_rad[0]: expected a finite number, got", "Write a finite number"},
    {"UnknownNoiseKey", "job.yaml", 0, "", "noise: {cameras: {cam1: {bogus: 1}}}\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:26:", "noise.cameras.cam1.bogus: unknown key",
     "Known keys: position_mm, rotation_rad"},
    {"SolverWithoutType", "job.yaml", 0, "  type: ceres_lm\n", "  max_iterations: 10\n",
     "run {job}", 2, Said::kOneLine, "job.yaml:13:3:", "solver: missing key 'type'",
     "Add 'type:' here"},
    {"ZeroIterations", "job.yaml", 0, "type: ceres_lm", "type: ceres_lm\n  max_iterations: 0",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:14:19:", "solver.max_iterations: must be between 1 and 1000000",
     "Allow at least one iteration; 200 is the default"},
    {"IterationsAWord", "job.yaml", 0, "type: ceres_lm", "type: ceres_lm\n  max_iterations: many",
     "run {job}", 2, Said::kOneLine, "job.yaml:14:19:",
     "solver.max_iterations: expected a whole number, got 'many'", "Write a whole number"},
    {"UnknownLoss", "job.yaml", 0, "type: ceres_lm", "type: ceres_lm\n  loss: l1", "run {job}", 2,
     Said::kOneLine, "job.yaml:14:9:", "solver.loss: unknown loss 'l1'",
     "Use none, huber or cauchy"},
    {"NegativeLossScale", "job.yaml", 0, "type: ceres_lm", "type: ceres_lm\n  loss_scale: -1",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:14:15:", "solver.loss_scale: must be between 1e-12 and 1e+09",
     "Give the residual size (mm) where the loss bends, above 0"},
    {"UnknownLinearSolver", "job.yaml", 0, "type: ceres_lm",
     "type: ceres_lm\n  linear_solver: cholesky", "run {job}", 2, Said::kOneLine,
     "job.yaml:14:18:", "solver.linear_solver: unknown linear solver 'cholesky'",
     "dense_qr, dense_normal_cholesky or sparse_normal_cholesky"},
    {"NegativeFunctionTolerance", "job.yaml", 0, "type: ceres_lm",
     "type: ceres_lm\n  function_tolerance: -1", "run {job}", 2, Said::kOneLine,
     "job.yaml:14:23:", "solver.function_tolerance: must be between 0 and 1",
     "A tolerance is a small non-negative number, e.g. 1e-14"},
    {"ParameterToleranceAboveOne", "job.yaml", 0, "type: ceres_lm",
     "type: ceres_lm\n  parameter_tolerance: 2", "run {job}", 2, Said::kOneLine,
     "job.yaml:14:24:", "solver.parameter_tolerance: must be between 0 and 1",
     "A tolerance is a small non-negative number, e.g. 1e-14"},
    {"GradientToleranceNan", "job.yaml", 0, "type: ceres_lm",
     "type: ceres_lm\n  gradient_tolerance: .nan", "run {job}", 2, Said::kOneLine,
     "job.yaml:14:23:", "solver.gradient_tolerance: expected a finite number, got '.nan'",
     "Write a finite number"},
    {"ZeroSolverThreads", "job.yaml", 0, "type: ceres_lm", "type: ceres_lm\n  threads: 0",
     "run {job}", 2, Said::kOneLine, "job.yaml:14:12:",
     "solver.threads: must be between 1 and 1024", "Use 1 or more threads; 2 is the default"},
    {"NegativeSolverThreads", "job.yaml", 0, "type: ceres_lm", "type: ceres_lm\n  threads: -2",
     "run {job}", 2, Said::kOneLine, "job.yaml:14:12:",
     "solver.threads: must be between 1 and 1024", "Use 1 or more threads; 2 is the default"},
    {"PinvNegativeRcond", "job.yaml", 0, "type: ceres_lm", "type: jacobian_pinv\n  rcond: -1",
     "run {job}", 2, Said::kOneLine, "job.yaml:14:10:", "solver.rcond: must be between 0 and 0.5",
     "singular value below which a direction is dropped: 1e-12"},
    {"PinvNegativeStepTolerance", "job.yaml", 0, "type: ceres_lm",
     "type: jacobian_pinv\n  step_tolerance: -1", "run {job}", 2, Said::kOneLine,
     "job.yaml:14:19:", "solver.step_tolerance: must be between 0 and 1",
     "A step in mm or rad below which the fit stops: 1e-10"},
    {"PinvZeroStep", "job.yaml", 0, "type: ceres_lm", "type: jacobian_pinv\n  max_step_mm: 0",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:14:16:", "solver.max_step_mm: must be between 1e-12 and 1e+09",
     "The largest change of a length per iteration, above 0"},
    {"PinvZeroIterations", "job.yaml", 0, "type: ceres_lm",
     "type: jacobian_pinv\n  max_iterations: 0", "run {job}", 2, Said::kOneLine,
     "job.yaml:14:19:", "solver.max_iterations: must be between 1 and 1000000",
     "Allow at least one iteration; 100 is the default"},
    {"NloptNegativeBox", "job.yaml", 0, "type: ceres_lm", "type: nlopt\n  box: -5", "run {job}", 2,
     Said::kOneLine, "job.yaml:14:8:", "solver.box: must be between 1e-12 and 1e+12",
     "search box's half-width in sigma-scaled units, above 0: 1e5"},
    {"NloptNegativeXtol", "job.yaml", 0, "type: ceres_lm", "type: nlopt\n  xtol_abs: -1",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:14:13:", "solver.xtol_abs: must be between 0 and 1000",
     "A step in sigma-scaled units, 0 or more: 1e-9"},
    {"NloptNegativeFtol", "job.yaml", 0, "type: ceres_lm", "type: nlopt\n  ftol_rel: -1",
     "run {job}", 2, Said::kOneLine, "job.yaml:14:13:", "solver.ftol_rel: must be between 0 and 1",
     "A relative cost change, 0 or more"},
    {"NloptZeroEvaluations", "job.yaml", 0, "type: ceres_lm", "type: nlopt\n  max_evaluations: 0",
     "run {job}", 2, Said::kOneLine, "job.yaml:14:20:",
     "solver.max_evaluations: must be between 1 and 100000000", "Allow at least one evaluation"},
    {"NloptZeroInitialStep", "job.yaml", 0, "type: ceres_lm", "type: nlopt\n  initial_step: 0",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:14:17:", "solver.initial_step: must be between 1e-12 and 1e+06",
     "A first step in sigma-scaled units, above 0: 10"},
    {"GradientDescentNegativeLearningRate", "job.yaml", 0, "type: ceres_lm",
     "type: gradient_descent\n  learning_rate: -1", "run {job}", 2, Said::kOneLine,
     "job.yaml:14:18:", "solver.learning_rate: must be positive, got -1",
     "Use a step in sigma-scaled units, e.g. 1e-3 (default) to 1"},
    {"GradientDescentZeroEpochs", "job.yaml", 0, "type: ceres_lm",
     "type: gradient_descent\n  epochs: 0", "run {job}", 2, Said::kOneLine,
     "job.yaml:14:11:", "solver.epochs: must be at least 1, got 0",
     "Use a whole number of full-batch steps, e.g. 5000 (default)"},
    {"GradientDescentUnknownKey", "job.yaml", 0, "type: ceres_lm",
     "type: gradient_descent\n  optimizer: sgd", "run {job}", 2, Said::kOneLine, "job.yaml:14:3:",
     "solver.optimizer: unknown key", "beta1, beta2, epsilon, gradient_tolerance, cost_tolerance"},
    {"GradientDescentBetaOne", "job.yaml", 0, "type: ceres_lm",
     "type: gradient_descent\n  beta1: 1", "run {job}", 2, Said::kOneLine,
     "job.yaml:14:10:", "solver.beta1: must be in [0, 1), got 1", "Use 0.9 (default)"},
    {"BaseFreeUnknownAxis", "job.yaml", 0, "base: {free: all}", "base: {free: [x, q]}", "run {job}",
     2, Said::kOneLine, "job.yaml:9:18:", "robots.ur3.base.free: unknown frame parameter 'q'",
     "Did you mean 'x'? Use x, y, z, rx, ry, rz, all or none"},
    {"BaseFreeTwice", "job.yaml", 0, "base: {free: all}", "base: {free: [x, x, y]}", "run {job}", 2,
     Said::kOneLine, "job.yaml:9:18:", "robots.ur3.base.free: 'x' appears twice in free",
     "Name each entry once"},
    {"FreeModelTwice", "job.yaml", 0, "base: {free: all}",
     "base: {free: all}\n    free_model: [j2.d, j2.d]", "run {job}", 2, Said::kOneLine,
     "job.yaml:10:17:", "robots.ur3.free_model: 'j2.d' appears twice in free_model",
     "Name each entry once"},
    {"BaseFreeAWord", "job.yaml", 0, "base: {free: all}", "base: {free: some}", "run {job}", 2,
     Said::kOneLine, "job.yaml:9:18:", "robots.ur3.base.free: unknown frame parameter 'some'",
     "Use x, y, z, rx, ry, rz, all or none"},
    {"ToolXyzOfTwoEntries", "job.yaml", 0, "xyz: [0, 0, 0]", "xyz: [0, 0]", "run {job}", 2,
     Said::kOneLine,
     "job.yaml:11:19:", "robots.ur3.tools.tool.xyz: expected a list of 3 numbers, got 2",
     "Give 3 numbers in brackets"},
    {"ToolXyzNan", "job.yaml", 0, "xyz: [0, 0, 0]", "xyz: [.nan, 0, 0]", "run {job}", 2,
     Said::kOneLine, "job.yaml:11:20:",
     "robots.ur3.tools.tool.xyz[0]: expected a finite number, got '.nan'", "Write a finite number"},
    {"ToolStartBeyondAnyCell", "job.yaml", 0, "xyz: [0, 0, 0]", "xyz: [1e300, 0, 0]", "run {job}",
     2, Said::kOneLine,
     "job.yaml:11:20:", "robots.ur3.tools.tool.xyz[0]: beyond any cell (|value| <= 1e5 mm)",
     "Give the position in mm, within 100 m"},
    {"ToolRotationVectorTooLong", "job.yaml", 0, "xyz: [0, 0, 0]",
     "xyz: [0, 0, 0], rvec: [100, 0, 0]", "run {job}", 2, Said::kOneLine,
     "job.yaml:11:37:", "robots.ur3.tools.tool.rvec[0]: longer than any rotation vector",
     "rotation vector in rad: its length is the angle, at most pi"},
    {"RobotWithoutModel", "job.yaml", 0, "    model: ", "    modl: ", "run {job}", 2,
     Said::kOneLine, "job.yaml:8:5:", "robots.ur3.modl: unknown key",
     "Known keys: model, base, tools, cameras, free_model, effects"},
    {"FreeModelUnknownParameter", "job.yaml", 0, "    base: {free: all}",
     "    base: {free: all}\n    free_model: [j9.d]", "run {job}", 2, Said::kOneLine,
     "job.yaml:10:17:", "robots.ur3.free_model: robot model 'serial_mdh' has no parameter",
     "Did you mean 'j1.d'?"},
    {"GravityOfTwoEntries", "job.yaml", 0, "", "gravity_base: [0, 0]\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:15:", "gravity_base: expected a list of 3 numbers, got 2",
     "Give 3 numbers in brackets"},
    {"GravityNan", "job.yaml", 0, "", "gravity_base: [0, 0, .nan]\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:22:", "gravity_base[2]: expected a finite number, got '.nan'",
     "Write a finite number"},
    {"EffectNotAMap", "job.yaml", 0, "    base: {free: all}",
     "    base: {free: all}\n    effects: [warp_drive]", "run {job}", 2, Said::kOneLine,
     "job.yaml:10:15:", "robots.ur3.effects[0]: expected a map of keys, got 'warp_drive'",
     "value' lines here (docs/formats.md lists each file's keys)"},
    {"UnknownJobKind", "job.yaml", 0, "job: workcell", "job: calibrate", "run {job}", 2,
     Said::kOneLine, "job.yaml:1:6:", "job: unknown job kind 'calibrate'",
     "Use workcell or homing"},
    {"NoJobKind", "job.yaml", 0, "job: workcell\n", "", "run {job}", 2, Said::kOneLine,
     "job.yaml:1:1:", "missing key 'job'", "Add 'job:' here"},
    {"MisspelledRecordingKey", "job.yaml", 0, "recording: ", "recordin: ", "run {job}", 2,
     Said::kOneLine, "job.yaml:3:1:", "recordin: unknown key",
     "gravity_base, uncertain_inputs, diagnosis, homing, outliers"},
    {"UnknownOutlierTest", "job.yaml", 0, "", "outliers: sometimes\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:11:", "outliers: unknown outlier test 'sometimes'",
     "Use robust (the default), plain or off"},
    {"ValidationRecordingMissing", "job.yaml", 0, "", "validation_recording: {dir}/nowhere\n",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:16:23:", "validation_recording: no recording at '{dir}/nowhere' (expected",
     "at a cellmetry-recording/1 folder, relative to the job file"},
    {"EmptyJob", "job.yaml", 0, "*", "", "run {job}", 2, Said::kOneLine,
     "job.yaml:", "expected a map of keys, got nothing",
     "value' lines here (docs/formats.md lists each file's keys)"},
    {"JobIsAList", "job.yaml", 0, "*", "- job: workcell\n", "run {job}", 2, Said::kOneLine,
     "job.yaml:1:1:", "expected a map of keys, got a list",
     "value' lines here (docs/formats.md lists each file's keys)"},
    {"TabIndentation", "job.yaml", 0, "*", "job: workcell\nrobots:\n\tur3: 1\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:3:5:", "YAML syntax: illegal map value",
     "Fix the YAML syntax (indentation, colons, brackets)"},
    {"UnclosedBrace", "job.yaml", 0, "validation:\n  folds: 5\n", "validation: {folds: 5\n",
     "run {job}", 2, Said::kOneLine, "job.yaml:15:1:", "YAML syntax: end of map flow not found",
     "Fix the YAML syntax (indentation, colons, brackets)"},
    {"BaseStartOfTwoEntries", "job.yaml", 0, "base: {free: all}",
     "base: {free: all, start: {xyz: [1, 2]}}", "run {job}", 2, Said::kOneLine,
     "job.yaml:9:36:", "robots.ur3.base.start.xyz: expected a list of 3 numbers, got 2",
     "Give 3 numbers in brackets"},
    {"BaseStartBeyondAnyCell", "job.yaml", 0, "base: {free: all}",
     "base: {free: all, start: {xyz: [1, -2e5, 0]}}", "run {job}", 2, Said::kOneLine,
     "job.yaml:9:40:", "robots.ur3.base.start.xyz[1]: beyond any cell (|value| <= 1e5 mm)",
     "Give the position in mm, within 100 m"},
    {"ToolFreeUnknownAxis", "job.yaml", 0, "free: [x, y, z]}", "free: [x, y, w]}", "run {job}", 2,
     Said::kOneLine, "job.yaml:11:36:", "robots.ur3.tools.tool.free: unknown frame parameter 'w'",
     "Did you mean 'x'? Use x, y, z, rx, ry, rz, all or none"},
    {"CameraStartNotInTheRecording", "job.yaml", 0, "", "cameras:\n  cam9: {xyz: [0, 0, 0]}\n",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:17:9:", "camera 'cam9' under cameras: is not in the recording {dir}/sim_b",
     "Name the cameras as recording.yaml does"},
    {"RobotTypeMissing", "ur3.yaml", 0, "type: serial_mdh\n", "", "run {job}", 2, Said::kOneLine,
     "ur3.yaml:4:1:", "missing key 'type'", "Add 'type:' here"},
    {"RobotWithNoJoints", "ur3.yaml", 0, "*",
     "type: serial_mdh\nunits: {length: mm, angle: rad}\njoints: []\n", "run {job}", 2,
     Said::kOneLine, "ur3.yaml:3:9:", "joints: no joints", "List one entry per joint"},
    {"RobotJointsNotAList", "ur3.yaml", 0, "*",
     "type: serial_mdh\nunits: {length: mm, angle: rad}\njoints: 6\n", "run {job}", 2,
     Said::kOneLine, "ur3.yaml:3:9:", "joints: expected a list, got '6'",
     "Write a list in brackets: [a, b, c]"},
    {"RobotAlphaNan", "ur3.yaml", 0, "{alpha: 0,                   a: 0,      d: 151.90",
     "{alpha: .nan,                   a: 0,      d: 151.90", "run {job}", 2, Said::kOneLine,
     "ur3.yaml:8:13:", "joints[0].alpha: expected a finite number, got '.nan'",
     "Write a finite number"},
    {"RobotLengthAWord", "ur3.yaml", 0, "a: 243.65", "a: long", "run {job}", 2, Said::kOneLine,
     "ur3.yaml:10:37:", "joints[2].a: expected a number, got 'long'", "Write a plain number"},
    {"RobotDBeyondAnyArm", "ur3.yaml", 0, "d: 119.85", "d: 1e300", "run {job}", 2, Said::kOneLine,
     "ur3.yaml:9:48:", "joints[1].d: beyond any arm (|d| <= 1000000 mm)",
     "Check the value and the units the config declares"},
    {"RobotOffsetBeyondAnyArm", "ur3.yaml", 0, "d: 151.90, offset: 0", "d: 151.90, offset: 1e9",
     "run {job}", 2, Said::kOneLine,
     "ur3.yaml:8:64:", "joints[0].offset: beyond any arm (|offset| <= 100 rad)",
     "Check the value and the units the config declares"},
    {"RobotBetaBeyondAnyArm", "ur3.yaml", 0, "d: 151.90, offset: 0",
     "d: 151.90, beta: 1e4, offset: 0", "run {job}", 2, Said::kOneLine,
     "ur3.yaml:8:62:", "joints[0].beta: beyond any arm (|beta| <= 100 rad)",
     "Check the value and the units the config declares"},
    {"RobotUnknownLengthUnit", "ur3.yaml", 0, "length: mm", "length: furlong", "run {job}", 2,
     Said::kOneLine, "ur3.yaml:6:17:", "units.length: unknown length unit 'furlong'",
     "Use mm or m"},
    {"RobotUnknownAngleUnit", "ur3.yaml", 0, "angle: rad", "angle: grad", "run {job}", 2,
     Said::kOneLine, "ur3.yaml:6:28:", "units.angle: unknown angle unit 'grad'", "Use rad or deg"},
    {"RobotFiveJointsForSixRecorded", "ur3.yaml", 0,
     "  - {alpha: 1.5707963267948966,  a: 0,      d: 81.90,  offset: 3.141592653589793}\n", "",
     "run {job}", 2, Said::kOneLine,
     "job.yaml:8:5:", "robot 'ur3' has 6 joints in the recording but 5 in {dir}/ur3.yaml",
     "Use the robot config that matches the recorded robot"},
    {"RobotUnknownJointKey", "ur3.yaml", 0, "d: 119.85,", "d: 119.85, theta: 0,", "run {job}", 2,
     Said::kOneLine, "ur3.yaml:9:56:", "joints[1].theta: unknown key",
     "Did you mean 'beta'? Known keys: alpha, a, beta, d, offset"},
    {"RobotTypeTwice", "ur3.yaml", 0, "type: serial_mdh", "type: serial_mdh\ntype: delta",
     "run {job}", 2, Said::kOneLine, "ur3.yaml:5:1:", "key 'type' appears twice in this map",
     "Keep one of them"},
    {"RobotUnknownKey", "ur3.yaml", 0, "name: UR3", "name: UR3\nmaker: UR", "run {job}", 2,
     Said::kOneLine, "ur3.yaml:6:1:", "maker: unknown key",
     "Known keys: type, name, description, units, joints"},
    {"RobotEmptyFile", "ur3.yaml", 0, "*", "", "run {job}", 2, Said::kOneLine,
     "ur3.yaml:", "expected a map of keys, got nothing",
     "value' lines here (docs/formats.md lists each file's keys)"},
    {"ObservationTooFewCells", "sim_b/observations.csv", 4, "", "1,cam1,tool,244.702809,-55.417908",
     "run {job}", 2, Said::kOneLine, "sim_b/observations.csv:4:6:", "column 'z': empty cell",
     "Fill in a number"},
    {"ObservationEmptyCell", "sim_b/observations.csv", 4, "",
     "1,cam1,tool,,-55.417908,725.561068,-2.15,1.60,0.53", "run {job}", 2, Said::kOneLine,
     "sim_b/observations.csv:4:4:", "column 'x': empty cell", "Fill in a number"},
    {"ObservationInfinite", "sim_b/observations.csv", 4, "",
     "1,cam1,tool,inf,-55.417908,725.561068,-2.15,1.60,0.53", "run {job}", 2, Said::kOneLine,
     "sim_b/observations.csv:4:4:", "column 'x': 'inf' is not a finite number",
     "Remove the row or replace the value with a measurement"},
    {"ObservationRotationNan", "sim_b/observations.csv", 4, "",
     "1,cam1,tool,244.702809,-55.417908,725.561068,nan,1.60,0.53", "run {job}", 2, Said::kOneLine,
     "sim_b/observations.csv:4:7:", "column 'rx': 'nan' is not a finite number",
     "Remove the row or replace the value with a measurement"},
    {"ObservationRotationPartlyFilled", "sim_b/observations.csv", 4, "",
     "1,cam1,tool,244.702809,-55.417908,725.561068,-2.15,1.60,", "run {job}", 2, Said::kOneLine,
     "sim_b/observations.csv:4:7:", "column 'rx': rotation is partly filled in",
     "Give all of rx,ry,rz or leave all three empty"},
    {"ObservationExtraCell", "sim_b/observations.csv", 4, "",
     "1,cam1,tool,244.702809,-55.417908,725.561068,-2.15,1.60,0.53,7", "run {job}", 2,
     Said::kOneLine, "sim_b/observations.csv:4:", "row has 10 cells but the header has 9",
     "Remove the extra cells or add their column to the header"},
    {"ObservationGivenTwice", "sim_b/observations.csv", 4, "",
     "0,cam1,tool,244.632864,-55.383274,725.424014,-2.155004972,1.601929886,0.536612874",
     "run {job}", 2, Said::kOneLine, "sim_b/observations.csv:4:3:",
     "column 'target': target 'tool' in sample 0 by camera 'cam1' was",
     "Keep one row per sample, camera and target"},
    {"ObservationNegativeSample", "sim_b/observations.csv", 4, "",
     "-1,cam1,tool,244.702809,-55.417908,725.561068,-2.15,1.60,0.53", "run {job}", 2,
     Said::kOneLine, "sim_b/observations.csv:4:1:", "column 'sample': unknown sample -1",
     "Every observation must name a sample listed in samples.csv"},
    {"ObservationSampleAWord", "sim_b/observations.csv", 4, "",
     "one,cam1,tool,244.702809,-55.417908,725.561068,-2.15,1.60,0.53", "run {job}", 2,
     Said::kOneLine, "sim_b/observations.csv:4:1:", "column 'sample': 'one' is not a number",
     "Write a plain decimal number"},
    {"ObservationHeaderWithoutX", "sim_b/observations.csv", 1, "",
     "sample,camera,target,y,z,rx,ry,rz", "run {job}", 2, Said::kOneLine,
     "sim_b/observations.csv:1:", "missing column 'x'", "The header must name it"},
    {"ObservationUnknownColumn", "sim_b/observations.csv", 1, "",
     "sample,camera,target,x,y,z,rx,ry,rz,colour", "run {job}", 2, Said::kOneLine,
     "sim_b/observations.csv:1:10:", "unknown column 'colour'",
     "Remove it or rename it to a known column"},
    {"SampleIdTwice", "sim_b/samples.csv", 5, "",
     "2,ur3,3,4.700736523,3.39327383,0.7314307094,4.095294476,5.03745842,0.69", "run {job}", 2,
     Said::kOneLine, "sim_b/samples.csv:5:1:", "column 'sample': sample 2 appears twice",
     "Give every captured state its own sample id"},
    {"SampleOfAnUnknownRobot", "sim_b/samples.csv", 5, "",
     "3,ur5,3,4.700736523,3.39327383,0.7314307094,4.095294476,5.03745842,0.69", "run {job}", 2,
     Said::kOneLine, "sim_b/samples.csv:5:2:", "column 'robot': unknown robot 'ur5'",
     "List it under 'robots' in recording.yaml"},
    {"SampleTooManyCells", "sim_b/samples.csv", 5, "",
     "3,ur3,3,4.700736523,3.39327383,0.7314307094,4.095294476,5.03745842,0.69,1", "run {job}", 2,
     Said::kOneLine, "sim_b/samples.csv:5:", "row has 10 cells but the header has 9",
     "Remove the extra cells or add their column to the header"},
    {"SampleJointInfinite", "sim_b/samples.csv", 5, "",
     "3,ur3,3,4.700736523,3.39327383,0.7314307094,-inf,5.03745842,0.69", "run {job}", 2,
     Said::kOneLine, "sim_b/samples.csv:5:7:", "column 'q4': '-inf' is not a finite number",
     "Remove the row or replace the value with a measurement"},
    {"SampleEmptyId", "sim_b/samples.csv", 5, "",
     ",ur3,3,4.700736523,3.39327383,0.7314307094,4.095294476,5.03745842,0.69", "run {job}", 2,
     Said::kOneLine, "sim_b/samples.csv:5:1:", "column 'sample': empty cell", "Fill in a number"},
    {"SampleFractionalId", "sim_b/samples.csv", 5, "",
     "3.5,ur3,3,4.700736523,3.39327383,0.7314307094,4.095294476,5.03745842,0.69", "run {job}", 2,
     Said::kOneLine, "sim_b/samples.csv:5:1:", "column 'sample': '3.5' is not a whole number",
     "Write a whole number"},
    {"SampleHeaderUnknownColumn", "sim_b/samples.csv", 1, "",
     "sample,robot,pose,q1,q2,q3,q4,q5,q6,speed", "run {job}", 2, Said::kOneLine,
     "sim_b/samples.csv:1:10:", "unknown column 'speed'",
     "Remove it or rename it to a known column"},
    {"RecordingFormatTwo", "sim_b/recording.yaml", 1, "", "format: cellmetry-recording/2",
     "run {job}", 2, Said::kOneLine,
     "sim_b/recording.yaml:1:9:", "format: unsupported format 'cellmetry-recording/2'",
     "This version reads cellmetry-recording/1"},
    {"RecordingUnknownLengthUnit", "sim_b/recording.yaml", 3, "",
     "units: {length: furlong, angle: rad}", "run {job}", 2, Said::kOneLine,
     "sim_b/recording.yaml:3:17:", "units.length: unknown length unit 'furlong'", "Use mm or m"},
    {"RecordingUnknownAngleUnit", "sim_b/recording.yaml", 3, "", "units: {length: mm, angle: grad}",
     "run {job}", 2, Said::kOneLine,
     "sim_b/recording.yaml:3:28:", "units.angle: unknown angle unit 'grad'", "Use rad or deg"},
    {"RecordingZeroJoints", "sim_b/recording.yaml", 5, "", "  ur3: {joints: 0}", "run {job}", 2,
     Said::kOneLine,
     "sim_b/recording.yaml:5:17:", "robots.ur3.joints: joint count must be between 1 and 64",
     "Give the robot's number of joints"},
    {"RecordingWithoutCameras", "sim_b/recording.yaml", 6, "", "cameras: []", "run {job}", 2,
     Said::kOneLine, "sim_b/observations.csv:2:2:", "column 'camera': unknown camera 'cam1'",
     "List it under 'cameras' in recording.yaml"},
    {"RecordingTargetOnAnUnknownRobot", "sim_b/recording.yaml", 8, "", "  tool: {on: ur5}",
     "run {job}", 2, Said::kOneLine,
     "sim_b/recording.yaml:8:14:", "targets.tool.on: target 'tool' is on unknown robot 'ur5'",
     "Use 'world' or a robot listed under 'robots'"},
    {"RecordingCameraOnAnUnknownRobot", "sim_b/recording.yaml", 6, "",
     "cameras: [{name: cam1, on: ur5}]", "run {job}", 2, Said::kOneLine,
     "sim_b/recording.yaml:6:28:", "cameras[0].on: camera 'cam1' is on unknown robot 'ur5'",
     "Use 'world' (a camera standing still) or a robot listed under 'robots'"},
    {"RecordingMisspelledKey", "sim_b/recording.yaml", 2, "", "descripton: typo", "run {job}", 2,
     Said::kOneLine, "sim_b/recording.yaml:2:1:", "descripton: unknown key",
     "keys: format, description, units, robots, cameras, targets"},
    {"RecordingWithoutUnits", "sim_b/recording.yaml", 3, "", "# no units", "run {job}", 2,
     Said::kOneLine, "sim_b/recording.yaml:1:1:", "missing key 'units'",
     "Add 'units: {length: mm, angle: rad}'"},
    {"RecordingCameraListedTwice", "sim_b/recording.yaml", 6, "", "cameras: [cam1, cam1]",
     "run {job}", 2, Said::kOneLine, "sim_b/recording.yaml:6:17:",
     "cameras[1]: camera 'cam1' is listed twice", "List each camera once"},
    {"RecordingTargetWithoutCarrier", "sim_b/recording.yaml", 8, "", "  tool: {}", "run {job}", 2,
     Said::kOneLine, "sim_b/recording.yaml:8:9:", "targets.tool: missing key 'on'",
     "Add 'on:' here"},
    {"SimulationNegativeSeed", "sim.yaml", 0, "seed: 7", "seed: -7",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine, "sim.yaml:15:7:",
     "seed: must be between 0 and 2147483647", "A seed is a whole number, 0 or more"},
    {"SimulationNegativePoseCount", "sim.yaml", 0, "random: 150", "random: -5",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine, "sim.yaml:22:21:",
     "robots.ur3.poses.random: must be between 1 and 1000000", "How many random poses to draw"},
    {"SimulationHugePoseCount", "sim.yaml", 0, "random: 150", "random: 2000000000",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine, "sim.yaml:22:21:",
     "robots.ur3.poses.random: must be between 1 and 1000000", "How many random poses to draw"},
    {"SimulationJointLimitsInverted", "sim.yaml", 0, "lower: [-6.2, 2.4", "lower: [7.0, 2.4",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:22:34:", "robots.ur3.poses.lower[0]: joint 1's lower limit is above its upper",
     "Give lower <= upper for every joint"},
    {"SimulationLowerLimitsOfThree", "sim.yaml", 0, "lower: [-6.2, 2.4, -2.2, -6.2, -6.2, -6.2]",
     "lower: [-6.2, 2.4, -2.2]", "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:22:33:", "robots.ur3.poses.lower: expected a list of 6 numbers, got 3",
     "Give 6 numbers in brackets"},
    {"SimulationNegativeNoise", "sim.yaml", 0, "position_mm: [0.05, 0.05, 0.2]",
     "position_mm: [0.05, -0.05, 0.2]", "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:31:23:", "noise.position_mm[1]: a standard deviation cannot be negative",
     "Give the noise's scatter, 0 or more"},
    {"SimulationRotationNoiseNan", "sim.yaml", 0, "rotation_rad: [0.0005, 0.0005, 0.001]",
     "rotation_rad: [0.0005, .nan, 0.001]", "simulate {dir}/sim.yaml -o {dir}/out", 2,
     Said::kOneLine, "sim.yaml:32:26:",
     "noise.rotation_rad[1]: expected a finite number, got '.nan'", "Write a finite number"},
    {"SimulationCameraXyzOfTwo", "sim.yaml", 0, "cam2: {xyz: [900, 300, 700]",
     "cam2: {xyz: [900, 300]", "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:28:15:", "cameras.cam2.xyz: expected a list of 3 numbers, got 2",
     "Give 3 numbers in brackets"},
    {"SimulationFieldOfViewBeyondAQuarterTurn", "sim.yaml", 0,
     "rvec: [-2.2936, -1.4001, 0.3616], half_fov_rad: [0.759",
     "rvec: [-2.2936, -1.4001, 0.3616], half_fov_rad: [1.7", "simulate {dir}/sim.yaml -o {dir}/out",
     2, Said::kOneLine, "sim.yaml:28:81:",
     "cameras.cam2.half_fov_rad[0]: a half angle of a field of view is between 0 and pi/2 rad",
     "Give half the image's width and height as angles"},
    {"SimulationWorldTargetOutOfView", "sim.yaml", 0, "rvec: [-2.2936, -1.4001, 0.3616]",
     "rvec: [2.2, -1.5, 0.3]", "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:28:9:", "cameras.cam2: the world target is outside this camera's field of view",
     "Aim the camera at the world's origin"},
    {"SimulationUnknownKind", "sim.yaml", 0, "simulation: workcell", "simulation: factory",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:14:13:", "simulation: unknown simulation kind 'factory'",
     "workcell (a delta arm is a cell too: docs/formats.md)"},
    {"SimulationRobotWithoutModel", "sim.yaml", 0,
     "    model: ", "    modl: ", "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:18:5:", "robots.ur3.modl: unknown key",
     "tools, cameras, model_errors, errors, poses, payloads_kg, effects"},
    {"SimulationRobotConfigMissing", "sim.yaml", 0, "    model: ",
     "    model: {dir}/missing.yaml  # ", "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:18:12:", "robots.ur3.model: robot config '{dir}/missing.yaml' not found",
     "Give a path relative to the job file"},
    {"SimulationNegativePayload", "sim.yaml", 0, "payloads_kg: [0, 1.0]", "payloads_kg: [0, -1.0]",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:24:18:", "robots.ur3.payloads_kg: a payload is a mass, 0 kg or more",
     "robots.ur3.payloads_kg: a payload is a mass, 0 kg or more"},
    {"SimulationTemperatureNan", "sim.yaml", 0, "temperature_end_c: 30", "temperature_end_c: .nan",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine, "sim.yaml:33:80:",
     "timeline.temperature_end_c: expected a finite number, got '.nan'", "Write a finite number"},
    {"SimulationNegativeCaptureInterval", "sim.yaml", 0, "seconds_per_sample: 20",
     "seconds_per_sample: -20", "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:33:32:", "timeline.seconds_per_sample: must be between 0 and 1e+07",
     "The time between captures, 0 s or more"},
    {"SimulationBaseBeyondAnyCell", "sim.yaml", 0, "base: {xyz: [431, 555, -460]",
     "base: {xyz: [431, 1e300, -460]", "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:19:23:", "robots.ur3.base.xyz[1]: beyond any cell (|value| <= 1e5 mm)",
     "Give the position in mm, within 100 m"},
    {"SimulationZeroRepeats", "sim.yaml", 0, "", "repeats: 0\n",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:34:10:", "repeats: must be between 1 and 1000", "Captures per commanded pose"},
    {"SimulationHugeRepeats", "sim.yaml", 0, "", "repeats: 100000000\n",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:34:10:", "repeats: must be between 1 and 1000", "Captures per commanded pose"},
    {"SimulationMisspelledPoseKey", "sim.yaml", 0, "random: 150", "randm: 150",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:22:13:", "robots.ur3.poses.randm: unknown key",
     "random, lower, upper, set, count, camera, seed, repeats"},
    {"SimulationGravityInfinite", "sim.yaml", 0, "", "gravity_base: [0, 0, .inf]\n",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine, "sim.yaml:34:22:",
     "gravity_base[2]: expected a finite number, got '.inf'", "Write a finite number"},
    {"SimulationToolRotationVectorTooLong", "sim.yaml", 0,
     "tool: {xyz: [0.5, -0.3, 66], rvec: [0.001, 0.002, -0.001]}",
     "tool: {xyz: [0.5, -0.3, 66], rvec: [0.001, 200, -0.001]}",
     "simulate {dir}/sim.yaml -o {dir}/out", 2, Said::kOneLine,
     "sim.yaml:21:50:", "robots.ur3.tools.tool.rvec[1]: longer than any rotation vector",
     "rotation vector in rad: its length is the angle, at most pi"},
    {"NoCommand", "", 0, "", "", "", 2, Said::kUsage, "", "A subcommand is required",
     "Run with --help for more information."},
    {"UnknownCommand", "", 0, "", "", "frobnicate {job}", 2, Said::kOneLine,
     "cellmetry:", "'frobnicate' is not a cellmetry command",
     "compare, detect, diagnose, plan, export, compensate, import, calibrate-camera, plugins"},
    {"UnknownGlobalOption", "", 0, "", "", "--chatty run {job}", 2, Said::kUsage, "",
     "The following argument was not expected: --chatty", "Run with --help for more information."},
    {"PluginPathMissing", "", 0, "", "", "--plugin-path {dir}/nowhere run {job}", 2, Said::kOneLine,
     "--plugin-path:", "no plugin folder at '{dir}/nowhere'",
     "--plugin-path at the folder that holds the plugin libraries"},
    {"PluginPathIsAFile", "", 0, "", "", "--plugin-path {job} run {job}", 2, Said::kOneLine,
     "--plugin-path:", "no plugin folder at '{dir}/job.yaml'",
     "--plugin-path at the folder that holds the plugin libraries"},
    {"PluginPathWithoutValue", "", 0, "", "", "run {job} --plugin-path", 2, Said::kUsage, "",
     "The following argument was not expected: --plugin-path",
     "Run with --help for more information."},
    {"RunWithoutJob", "", 0, "", "", "run", 2, Said::kUsage, "", "job is required",
     "Run with --help for more information."},
    {"RunJobMissing", "", 0, "", "", "run {dir}/nojob.yaml", 2, Said::kOneLine, "nojob.yaml:",
     "cannot open file", "path (relative paths in a job are relative to the job file)"},
    {"RunJobIsAFolder", "", 0, "", "", "run {dir}/sim_b", 2, Said::kOneLine,
     "sim_b:", "is a folder, not a YAML file", "Give the path of the YAML file itself"},
    {"RunJobIsEmpty", "", 0, "", "", "run {dir}/empty.yaml", 2, Said::kOneLine,
     "empty.yaml:", "expected a map of keys, got nothing",
     "value' lines here (docs/formats.md lists each file's keys)"},
    {"RunJobIsACsvFile", "", 0, "", "", "run {dir}/sim_b/samples.csv", 2, Said::kOneLine,
     "sim_b/samples.csv:1:1:", "expected a map of keys, got 'sample,robot,pose,q1,q2,q3,q4,q5,q6",
     "value' lines here (docs/formats.md lists each file's keys)"},
    {"RunOutputWithoutValue", "", 0, "", "", "run {job} -o", 2, Said::kUsage, "",
     "--output: 1 required TEXT missing", "Run with --help for more information."},
    {"RunOutputIsAFile", "", 0, "", "", "run {job} -o {dir}/notes.txt", 2, Said::kOneLine,
     "notes.txt:", "the output path is an existing file; cellmetry writes a folder there",
     "Choose another output folder (output: in the job, or -o)"},
    {"RunOutputIsTheRecording", "", 0, "", "", "run {job} -o {dir}/sim_b", 2, Said::kOneLine,
     "sim_b:", "the output folder exists and was not written by cellmetry (no",
     "or remove it yourself (an older cellmetry's output too)"},
    {"RunOutputIsTheWorkingDirectory", "", 0, "", "", "run {job} -o .", 2, Said::kOneLine,
     ".:", "the output folder holds the working directory",
     "Choose another output folder (output: in the job, or -o)"},
    {"RunWithoutAnUnknownCamera", "", 0, "", "", "run {job} --without cam9 -o {dir}/out", 2,
     Said::kOneLine, "job.yaml:", "--without cam9: no such camera in {dir}/sim_b",
     "Name a camera as recording.yaml does"},
    {"DiagnoseWithoutAnUnknownCamera", "", 0, "", "", "diagnose {job} --without cam9 -o {dir}/d", 2,
     Said::kOneLine, "job.yaml:", "--without cam9: no such camera in {dir}/sim_b",
     "Name a camera as recording.yaml does"},
    {"RunTwoJobs", "", 0, "", "", "run {job} {job}", 2, Said::kUsage, "",
     "The following argument was not expected: {dir}/job.yaml",
     "Run with --help for more information."},
    {"RunUnknownOption", "", 0, "", "", "run {job} --fast", 2, Said::kUsage, "",
     "The following argument was not expected: --fast", "Run with --help for more information."},
    {"SimulateWithoutOutput", "", 0, "", "", "simulate {dir}/sim.yaml", 2, Said::kUsage, "",
     "--output is required", "Run with --help for more information."},
    {"SimulateSpecMissing", "", 0, "", "", "simulate {dir}/nosim.yaml -o {dir}/out", 2,
     Said::kOneLine, "nosim.yaml:", "cannot open file",
     "path (relative paths in a job are relative to the job file)"},
    {"SimulateOntoAFile", "", 0, "", "", "simulate {dir}/sim.yaml -o {dir}/notes.txt", 2,
     Said::kOneLine,
     "notes.txt:", "the output path is an existing file; cellmetry writes a folder there",
     "Choose another output folder (output: in the job, or -o)"},
    {"SimulateAWorkcellJob", "", 0, "", "", "simulate {job} -o {dir}/out", 2, Said::kOneLine,
     "job.yaml:1:1:", "job: unknown key",
     "repeats, images, effects, timeline, concealed, gravity_base"},
    {"SimulateOntoTheRecording", "", 0, "", "", "simulate {dir}/sim.yaml -o {dir}/sim_b", 2,
     Said::kOneLine, "sim_b:", "the output folder exists and was not written by cellmetry (no",
     "or remove it yourself (an older cellmetry's output too)"},
    {"EvaluateWithoutTruth", "", 0, "", "", "evaluate {dir}/result", 2, Said::kUsage, "",
     "truth is required", "Run with --help for more information."},
    {"EvaluateResultMissing", "", 0, "", "", "evaluate {dir}/noresult {dir}/sim.yaml", 2,
     Said::kOneLine, "noresult/result.json:", "cannot open result", "Run the job first"},
    {"EvaluateARecordingAsResult", "", 0, "", "", "evaluate {dir}/sim_b {dir}/sim.yaml", 2,
     Said::kOneLine, "sim_b/result.json:", "cannot open result", "Run the job first"},
    {"HomeWithoutJob", "", 0, "", "", "home", 2, Said::kUsage, "", "job is required",
     "Run with --help for more information."},
    {"HomeAWorkcellJob", "", 0, "", "", "home {job}", 2, Said::kOneLine,
     "job.yaml:", "not a homing job (job: workcell)", "Run workcell jobs with 'cellmetry run'"},
    {"HomeJobMissing", "", 0, "", "", "home {dir}/nojob.yaml", 2, Said::kOneLine, "nojob.yaml:",
     "cannot open file", "path (relative paths in a job are relative to the job file)"},
    {"CompareZeroSeeds", "", 0, "", "", "compare {dir}/cmp.yaml --seeds 0", 2, Said::kUsage, "",
     "--seeds: Value 0 not in range 1 to 100000", "Run with --help for more information."},
    {"CompareTooManySeeds", "", 0, "", "", "compare {dir}/cmp.yaml --seeds 100001", 2, Said::kUsage,
     "", "--seeds: Value 100001 not in range 1 to 100000", "Run with --help for more information."},
    {"CompareSeedsAWord", "", 0, "", "", "compare {dir}/cmp.yaml --seeds many", 2, Said::kUsage, "",
     "--seeds: Value many not in range 1 to 100000", "Run with --help for more information."},
    {"CompareSpecMissing", "", 0, "", "", "compare {dir}/nocmp.yaml", 2, Said::kOneLine,
     "nocmp.yaml:", "cannot open file",
     "path (relative paths in a job are relative to the job file)"},
    {"CompareAWorkcellJob", "", 0, "", "", "compare {job}", 2, Said::kOneLine,
     "job.yaml:1:1:", "missing key 'compare'", "Add 'compare:' here"},
    {"CompareUnknownKind", "", 0, "", "", "compare {dir}/cmp.yaml", 2, Said::kOneLine,
     "cmp.yaml:1:10:", "compare: unknown comparison 'everything'",
     "or hand_eye (cellmetry against OpenCV's hand-eye methods); docs/formats.md"},
    {"DetectNegativeLimit", "", 0, "", "", "detect {job} --limit -1", 2, Said::kUsage, "",
     "--limit: Value -1 not in range 0 to 1000000000", "Run with --help for more information."},
    {"DetectLimitAWord", "", 0, "", "", "detect {job} --limit all", 2, Said::kUsage, "",
     "--limit: Value all not in range 0 to 1000000000", "Run with --help for more information."},
    {"DetectAWorkcellJob", "", 0, "", "", "detect {job}", 2, Said::kOneLine,
     "job.yaml:1:6:", "job: not a detect job (job: workcell)",
     "the command its kind names; a detect job says job: detect"},
    {"DetectJobMissing", "", 0, "", "", "detect {dir}/nojob.yaml", 2, Said::kOneLine, "nojob.yaml:",
     "cannot open file", "path (relative paths in a job are relative to the job file)"},
    {"DiagnoseJobMissing", "", 0, "", "", "diagnose {dir}/nojob.yaml", 2, Said::kOneLine,
     "nojob.yaml:", "cannot open file",
     "path (relative paths in a job are relative to the job file)"},
    {"DiagnoseOutputIsAFile", "", 0, "", "", "diagnose {job} -o {dir}/notes.txt", 2, Said::kOneLine,
     "notes.txt:", "the output path is an existing file; cellmetry writes a folder there",
     "Choose another output folder (output: in the job, or -o)"},
    {"PlanZeroPoses", "", 0, "", "", "plan {job} -n 0", 2, Said::kUsage, "",
     "--poses: Value 0 not in range 1 to 10000", "Run with --help for more information."},
    {"PlanTooManyPoses", "", 0, "", "", "plan {job} -n 10001", 2, Said::kUsage, "",
     "--poses: Value 10001 not in range 1 to 10000", "Run with --help for more information."},
    {"PlanPosesAWord", "", 0, "", "", "plan {job} -n ten", 2, Said::kUsage, "",
     "--poses: Value ten not in range 1 to 10000", "Run with --help for more information."},
    {"PlanZeroDraws", "", 0, "", "", "plan {job} --draws 0", 2, Said::kUsage, "",
     "--draws: Value 0 not in range 1 to 1000000", "Run with --help for more information."},
    {"PlanTooManyDraws", "", 0, "", "", "plan {job} --draws 1000001", 2, Said::kUsage, "",
     "--draws: Value 1000001 not in range 1 to 1000000", "Run with --help for more information."},
    {"PlanUnknownEffect", "", 0, "", "", "plan {job} --effect ur3.warp_j2 -o {dir}/plan", 2,
     Said::kOneLine, "--effect:", "no candidate effect 'ur3.warp_j2'",
     "target.scale_world, target.tilt_world, world_frame"},
    {"PlanOutputIsAFile", "", 0, "", "", "plan {job} -o {dir}/notes.txt", 2, Said::kOneLine,
     "notes.txt:", "the output path is an existing file; cellmetry writes a folder there",
     "Choose another output folder (output: in the job, or -o)"},
    {"ExportWithoutFormat", "", 0, "", "", "export {dir}/result", 2, Said::kUsage, "",
     "--format is required", "Run with --help for more information."},
    {"ExportUnknownFormat", "", 0, "", "", "export {dir}/result -f pdf", 2, Said::kOneLine,
     "--format:", "unknown export format 'pdf'", "Give one of: urdf, ur, tf, robot"},
    {"ExportResultMissing", "", 0, "", "", "export {dir}/noresult -f urdf", 2, Said::kOneLine,
     "noresult:", "no such result folder", "Give the folder `cellmetry run` wrote (its `output:`)"},
    {"ExportARecordingAsResult", "", 0, "", "", "export {dir}/sim_b -f urdf", 2, Said::kOneLine,
     "sim_b/result.json:", "cannot open the result",
     "Give the folder `cellmetry run` wrote (its `output:`)"},
    {"ImportWithoutOutput", "", 0, "", "", "import {dir}/map.yaml", 2, Said::kUsage, "",
     "--output is required", "Run with --help for more information."},
    {"ImportMappingMissing", "", 0, "", "", "import {dir}/nomap.yaml -o {dir}/out", 2,
     Said::kOneLine, "nomap.yaml:", "cannot open file",
     "path (relative paths in a job are relative to the job file)"},
    {"ImportAWorkcellJob", "", 0, "", "", "import {job} -o {dir}/out", 2, Said::kOneLine,
     "job.yaml:1:1:", "job: unknown key",
     "units, robot, samples, poses, targets, observations, facts"},
    {"ImportTwoTablesWithoutAJoin", "map.yaml", 0, "*",
     "mapping: cellmetry-import/1\ntables: {robot: robot.csv, tracker: tracker.csv}\n",
     "import {dir}/map.yaml -o {dir}/out", 2, Said::kOneLine, "map.yaml:1:1:", "missing key 'join'",
     "Say how the tables' rows belong together: join: {by: row}"},
    {"ImportJoinedByAnUnknownWay", "map.yaml", 0, "*",
     "mapping: cellmetry-import/1\ntables: {robot: robot.csv, tracker: tracker.csv}\n"
     "join: {by: rows}\n",
     "import {dir}/map.yaml -o {dir}/out", 2, Said::kOneLine,
     "map.yaml:3:12:", "unknown join 'rows'", "Did you mean 'row'?"},
    {"ImportOntoAFile", "", 0, "", "", "import {dir}/map.yaml -o {dir}/notes.txt", 2,
     Said::kOneLine,
     "notes.txt:", "the output path is an existing file; cellmetry writes a folder there",
     "Choose another output folder (output: in the job, or -o)"},
    {"PluginsExtraWord", "", 0, "", "", "plugins all", 2, Said::kUsage, "",
     "The following argument was not expected: all", "Run with --help for more information."},
    {"PluginsUnknownOption", "", 0, "", "", "plugins --json", 2, Said::kUsage, "",
     "The following argument was not expected: --json", "Run with --help for more information."},
    {"ExportUnknownRobot", "", 0, "", "", "export {result} -f urdf --robot ur5", 2, Said::kOneLine,
     "result/result.json:", "the result has no robot 'ur5'", "Its robots: ur3"},
    {"ExportOntoAUsersFile", "", 0, "", "", "export {result} -f urdf -o {dir}/notes.txt", 2,
     Said::kOneLine, "notes.txt:", "the file exists and was not written by `cellmetry export`",
     "or give --overwrite to replace it"},
    {"ExportOntoAFolder", "", 0, "", "", "export {result} -f ur -o {dir}/sim_b", 2, Said::kOneLine,
     "sim_b:", "the export path is not a file (a folder?)", "Choose another file with -o"},
    {"EvaluateTruthMissing", "", 0, "", "", "evaluate {result} {dir}/notruth.yaml", 2,
     Said::kOneLine, "notruth.yaml:", "cannot open file", "Check the path"},
    {"EvaluateAJobAsTruth", "", 0, "", "", "evaluate {result} {job}", 2, Said::kOneLine,
     "job.yaml:1:1:", "job: unknown key", "Known keys: format, frames, model"},
    {"EvaluateNotesAsTruth", "", 0, "", "", "evaluate {result} {dir}/notes.txt", 2, Said::kOneLine,
     "notes.txt:1:1:", "expected a map of keys, got 'mine'", "Write 'key: value' lines here"},
    // Read as written or refused, and bounded: the second pass's rows.
    {"OverlongSolverTypeIsQuotedShort", "job.yaml", 0, "type: ceres_lm",
     "type: " + std::string(5000, 'x'), "run {job}", 2, Said::kOneLine, "job.yaml:13:9:",
     "unknown solver type '" + std::string(80, 'x') + "...'", "Known solver types"},
    {"SecondYamlDocument", "job.yaml", 0, "", "---\nsolver: {type: ceres_lm}\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:1:", "a second YAML document in one file ('---' starts it)",
     "cellmetry reads one document per file: remove the '---' and what follows, or put it in a "
     "file of its own"},
    {"ContentAfterTheDocumentEnd", "job.yaml", 0, "", "...\nsolver: {type: nlopt}\n", "run {job}",
     2, Said::kOneLine, "job.yaml:17:1:", "a second YAML document in one file ('---' starts it)",
     "remove the '---' and what follows"},
    {"YamlAliasBombInTheJob", "job.yaml", 0, "", kAliasBomb, "run {job}", 2, Said::kOneLine,
     "job.yaml:16:34:", "more than 100000 values once anchors (&) and aliases (*) are expanded",
     "Write the values out, or use fewer aliases"},
    {"YamlAliasInsideItsOwnAnchor", "job.yaml", 0, "", "loop: &l [x, *l]\n", "run {job}", 2,
     Said::kOneLine, "job.yaml:16:11:",
     "values nested more than 64 deep (or an alias (*) inside its own anchor (&))",
     "Write the values out"},
    {"YamlAliasBombInRecordingYaml", "sim_b/recording.yaml", 0, "", kAliasBomb, "run {job}", 2,
     Said::kOneLine, "recording.yaml:10:28:",
     "more than 100000 values once anchors (&) and aliases (*) are expanded",
     "Write the values out, or use fewer aliases"},
    {"YamlAliasBombInTheRobotConfig", "ur3.yaml", 0, "", kAliasBomb, "run {job}", 2, Said::kOneLine,
     "ur3.yaml:14:28:", "more than 100000 values once anchors (&) and aliases (*) are expanded",
     "Write the values out, or use fewer aliases"},
    {"YamlAliasBombInAMapping", "map.yaml", 0, "", kAliasBomb, "import {dir}/map.yaml -o {dir}/out",
     2, Said::kOneLine,
     "map.yaml:2:10:", "more than 100000 values once anchors (&) and aliases (*) are expanded",
     "Write the values out, or use fewer aliases"},
    {"BootstrapBeyondItsLimit", "job.yaml", 0, "", "diagnosis: {bootstrap: 1000000000}\n",
     "diagnose {job} -o {dir}/d", 2, Said::kOneLine,
     "job.yaml:16:24:", "diagnosis.bootstrap: must be between 0 and 10000",
     "40 resamples is the default; 10,000 the most"},
    {"RivalDrawsBeyondTheirLimit", "job.yaml", 0, "", "diagnosis: {rival_draws: 1000000000}\n",
     "diagnose {job} -o {dir}/d", 2, Said::kOneLine,
     "job.yaml:16:26:", "diagnosis.rival_draws: must be between 100 and 1000000",
     "Use 100 or more draws; 2000 is the default"},
    {"NegativeLinkMass", "job.yaml", 0, "", "diagnosis: {link_masses_kg: [2, -3, 1, 1, 1, 1]}\n",
     "diagnose {job} -o {dir}/d", 2, Said::kOneLine,
     "job.yaml:16:29:", "diagnosis.link_masses_kg: a link's mass is 0 to 10,000 kg",
     "Give each link's mass in kg, 0 for a massless link"},
    {"HomeZeroSigma", "job.yaml", 0, "*",
     "job: homing\nrecording: {dir}/sim_b\noutput: {dir}/h\nworld_target: none\nrobots:\n"
     "  delta:\n    model: {src}/robots/delta.yaml\n    tools:\n      marker:\n"
     "cameras:\n  stereo: {xyz: [0, 250, -150], rvec: [3.0, 0, 0]}\n"
     "noise: {cameras: {stereo: {position_mm: [0.013, 0.012, 0.058]}}}\n"
     "homing: {n_sigma: 0}\n",
     "home {job}", 2, Said::kOneLine,
     "job.yaml:13:19:", "homing.n_sigma: must be between 0.001 and 100",
     "How many sigma an interval spans: 3 is usual"},
    {"CompensateNegativeTolerance", "", 0, "", "",
     "compensate {dir}/result {dir}/targets.csv --tolerance-mm -1", 2, Said::kUsage, "",
     "--tolerance-mm: Value -1 not in range", "Run with --help for more information."},
    {"CompensateToleranceNan", "", 0, "", "",
     "compensate {dir}/result {dir}/targets.csv --tolerance-mm nan", 2, Said::kUsage, "",
     "--tolerance-mm: Value nan is not a finite number", "Run with --help for more information."},
    {"CompensateZeroRotationTolerance", "", 0, "", "",
     "compensate {dir}/result {dir}/targets.csv --tolerance-rad 0", 2, Said::kUsage, "",
     "--tolerance-rad: Value 0 not in range", "Run with --help for more information."},
    {"CompensateZeroIterations", "", 0, "", "",
     "compensate {dir}/result {dir}/targets.csv --max-iterations 0", 2, Said::kUsage, "",
     "--max-iterations: Value 0 not in range 1 to 100000", "Run with --help for more information."},
    {"CompensateNegativeJointLimitMargin", "", 0, "", "",
     "compensate {dir}/result {dir}/targets.csv --joint-limit-margin-rad -0.1", 2, Said::kUsage, "",
     "--joint-limit-margin-rad: Value -0.1 not in range", "Run with --help for more information."},
    {"CompareKinematicWithoutPoseSets", "cmp.yaml", 0, "*",
     "compare: kinematic\nsimulation: {src}/compare/delta_table7_simulation.yaml\npose_sets: []\n"
     "sizes: [24]\nformulations: [forward]\nsolvers: {lm: {type: ceres_lm}}\n",
     "compare {dir}/cmp.yaml -o {dir}/cmp", 2, Said::kOneLine, "cmp.yaml:3:12:",
     "pose_sets: lists nothing: the table would have no rows", "Give at least one entry"},
    {"CompareKinematicWithoutSolvers", "cmp.yaml", 0, "*",
     "compare: kinematic\nsimulation: {src}/compare/delta_table7_simulation.yaml\n"
     "pose_sets: [camera_view]\nsizes: [24]\nformulations: [forward]\nsolvers: {}\n",
     "compare {dir}/cmp.yaml -o {dir}/cmp", 2, Said::kOneLine, "cmp.yaml:6:10:",
     "solvers: lists nothing: the table would have no rows", "Give at least one entry"},
    {"CompareSolversWithoutSolvers", "cmp.yaml", 0, "*",
     "compare: solvers\njob: job.yaml\nsolvers: {}\n", "compare {dir}/cmp.yaml -o {dir}/cmp", 2,
     Said::kOneLine, "cmp.yaml:3:10:", "solvers: lists no solver: the table would have no rows",
     "Give at least one, e.g. lm: {type: ceres_lm}"},
    {"CompareSolversWithoutCameraModels", "cmp.yaml", 0, "*",
     "compare: solvers\njob: job.yaml\nsolvers: {lm: {type: ceres_lm}}\ncamera_models: []\n",
     "compare {dir}/cmp.yaml -o {dir}/cmp", 2, Said::kOneLine,
     "cmp.yaml:4:16:", "camera_models: lists no camera model: the table would have no rows",
     "Give static_cameras, per_frame or both"},
    {"CompareMarkersWithoutDetectors", "cmp.yaml", 0, "*", "compare: markers\ndetectors: {}\n",
     "compare {dir}/cmp.yaml -o {dir}/cmp", 2, Said::kOneLine, "cmp.yaml:2:12:",
     "detectors: lists no detector: the tables would have no rows", "Give at least one"},
    {"CompareMarkersOneCapture", "cmp.yaml", 0, "*",
     "compare: markers\ndetectors: {dot: {type: dot, diameter_mm: 10}}\ncaptures: 1\n",
     "compare {dir}/cmp.yaml -o {dir}/cmp", 2, Said::kOneLine,
     "cmp.yaml:3:11:", "captures: must be between 2 and 100000", "at least 2 for a sigma"},
    {"ComparePhysicsCellWithoutCases", "cmp.yaml", 0, "*",
     "compare: physics\ncells:\n  - {name: a, simulation: sim.yaml, job: job.yaml, cases: []}\n",
     "compare {dir}/cmp.yaml -o {dir}/cmp", 2, Said::kOneLine, "cmp.yaml:3:59:",
     "lists no case: the cell would add nothing to the table", "Give at least one case"},
};

INSTANTIATE_TEST_SUITE_P(EveryCommand, BadCommand, ::testing::ValuesIn(kBadCases),
                         [](const ::testing::TestParamInfo<BadCase>& info) {
                           return info.param.name;
                         });

// A recording file that is not a regular file: a FIFO blocked the read forever, a link to
// /dev/zero was read until memory ran out. Both are refused before they are opened.
TEST_F(BadInput, ARecordingFileThatIsAFifoOrADeviceIsRefusedAtOnce) {
  WriteJob();
  fs::remove(recording_ + "/observations.csv");
  ASSERT_EQ(::mkfifo((recording_ + "/observations.csv").c_str(), 0600), 0);
  const auto fifo = Run();
  ExpectRejected(fifo, "observations.csv:", "Put a regular file there");
  EXPECT_THAT(fifo.output, HasSubstr("is a FIFO (named pipe), not a regular file"));
  fs::remove(recording_ + "/observations.csv");
  fs::copy_file(testing::Source("tests/data/vsb/sim_b/observations.csv"),
                recording_ + "/observations.csv");
  fs::remove(recording_ + "/samples.csv");
  fs::create_symlink("/dev/zero", recording_ + "/samples.csv");
  const auto zero = Run();
  ExpectRejected(zero, "samples.csv:", "Put a regular file there");
  EXPECT_THAT(zero.output, HasSubstr("is a character device, not a regular file"));
}

// A few lines of anchors and aliases name one node 387 million times: refused at once with the
// limit named (it took 20 s at 9 levels and more than 120 s at 10).
TEST_F(BadInput, AYamlAliasBombIsRefusedWithinASecond) {
  std::string ten_levels = kAliasBomb;
  ten_levels += "a10: &a10 [*a9, *a9, *a9, *a9, *a9, *a9, *a9, *a9, *a9]\n";
  WriteJob(JobText() + ten_levels);
  const auto start = std::chrono::steady_clock::now();
  const auto r = Run();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ExpectRejected(r, "job.yaml:16:34:", "Write the values out, or use fewer aliases");
  EXPECT_THAT(r.output, HasSubstr("more than 100000 values once anchors"));
  EXPECT_LT(seconds, 5.0) << "the sanitizers' build is slower; a release build takes 0.1 s";
}

// A fit takes about 5.5 KB per observation row: a recording table of more than 150,000 rows is
// refused before a row is parsed (its rows counted in one pass over the bytes), the limit and
// what to do named. 2 million rows took 1.8-2.2 GB to read, and a fit on them many more.
TEST_F(BadInput, ATableOfMoreRowsThanAFitHoldsIsRefusedBeforeItIsParsed) {
  WriteJob();
  for (const char* file : {"observations.csv", "samples.csv"}) {
    const std::string path = recording_ + "/" + file;
    const std::string original = ReadText(path);
    const size_t rows = std::count(original.begin(), original.end(), '\n') - 1;
    std::string more = original;
    for (size_t row = rows; row <= 150000; ++row) more += "x\n";  // refused before it is read
    testing::WriteText(path, more);
    const auto start = std::chrono::steady_clock::now();
    const auto r = Run();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ExpectRejected(r, std::string(file) + ":",
                   "split it into recordings of at most 150000 rows each");
    EXPECT_THAT(r.output, HasSubstr("has 150001 rows, more than the 150000"));
    EXPECT_LT(seconds, 5.0) << "a release build takes 0.1 s";
    testing::WriteText(path, original);
  }
}

// What `cellmetry ARGUMENTS` prints, stdout and stderr, without the -q RunCellmetry gives.
std::string OutputWithProgress(const std::string& arguments) {
  FILE* pipe = popen((std::string(CELLMETRY_BINARY) + " " + arguments + " 2>&1").c_str(), "r");
  std::string output;
  char buffer[4096];
  for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
  pclose(pipe);
  return output;
}

// Reading a table of more than 100,000 rows says how far it has got, unless --quiet; a small
// table's reading says nothing. (A tool the recording lacks stops the run once it is read.)
TEST_F(BadInput, ReadingALargeTableShowsProgressUnlessQuiet) {
  WriteJob(ReplaceOnce(JobText(), "      tool: {", "      no_such_tool: {"));
  const std::string small = OutputWithProgress("run " + job_);
  EXPECT_THAT(small, HasSubstr("'no_such_tool' is not carried"));
  EXPECT_THAT(small, ::testing::Not(HasSubstr("reading samples.csv")));
  std::istringstream original(ReadText(recording_ + "/samples.csv"));
  std::string header, line;
  std::getline(original, header);
  std::vector<std::string> joints;  // each sample's q1..q6, as written
  while (std::getline(original, line)) {
    joints.push_back(line.substr(line.find(',', line.find(',', line.find(',') + 1) + 1)));
  }
  std::string samples = header + "\n";
  for (size_t id = 0; id <= 100000; ++id) {  // sim_b's samples first, then repeats as new poses
    const std::string& q = joints[id % joints.size()];
    samples += std::to_string(id) + ",ur3," + std::to_string(id) + q + "\n";
  }
  testing::WriteText(recording_ + "/samples.csv", samples);
  const std::string large = OutputWithProgress("run " + job_);
  EXPECT_THAT(large, HasSubstr("cellmetry: reading samples.csv rows 100001/100001"));
  EXPECT_THAT(large, HasSubstr("'no_such_tool' is not carried"));
  const std::string quiet = OutputWithProgress("--quiet run " + job_);
  EXPECT_THAT(quiet, HasSubstr("'no_such_tool' is not carried"));
  EXPECT_THAT(quiet, ::testing::Not(HasSubstr("reading samples.csv")));
}

TEST_F(BadInput, RobotJointWithoutDIsRefusedNotReadAsZero) {
  WriteJob();
  testing::WriteText(robot_, ReplaceOnce(ReadText(robot_), "d: 151.90, ", ""));
  const auto r = Run();
  ExpectRejected(r, "ur3.yaml:8:5:", "Add 'd:' here");
  EXPECT_THAT(r.output, HasSubstr("joints[0]: missing key 'd'"));
}

TEST_F(BadInput, AByteOrderMarkBeforeTheHeaderIsNotPartOfTheFirstColumn) {
  WriteJob();
  testing::WriteText(recording_ + "/samples.csv",
                     "\xEF\xBB\xBF" + ReadText(recording_ + "/samples.csv"));
  const auto r = Run();
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// observations.csv with every position multiplied by `scale` (a unit mix-up), rotations kept.
std::string ScaledObservations(const std::string& text, double scale) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream split(line);
    for (std::string cell; std::getline(split, cell, ',');) cells.push_back(cell);
    if (out.empty()) {
      out += line + "\n";  // the header
      continue;
    }
    for (int i = 3; i < 6; ++i) {
      char number[32];
      std::snprintf(number, sizeof(number), "%.9g", std::stod(cells[i]) * scale);
      cells[i] = number;
    }
    for (size_t i = 0; i < cells.size(); ++i) out += (i ? "," : "") + cells[i];
    out += "\n";
  }
  return out;
}

TEST_F(BadInput, RecordingInMetresDeclaredMillimetresIsRefusedWithTheLikelyCause) {
  WriteJob();
  testing::WriteText(recording_ + "/observations.csv",
                     ScaledObservations(ReadText(recording_ + "/observations.csv"), 1e-3));
  const auto r = Run();
  ExpectRejected(r, "sim_b/recording.yaml:3:17:",
                 "The recording's numbers look like metres but recording.yaml declares length: "
                 "mm: declare units: {length: m}");
  EXPECT_THAT(r.output, HasSubstr("the recording and robot ur3 disagree in size by about 1000 "
                                  "times: target 'tool' moves over 0.277 mm in cam1"));
}

TEST_F(BadInput, RobotConfigInMillimetresDeclaredMetresIsBlamedNotTheRecording) {
  WriteJob();
  testing::WriteText(robot_, ReplaceOnce(ReadText(robot_), "length: mm", "length: m"));
  const auto r = Run();
  ExpectRejected(r, "ur3.yaml:6:17:",
                 "the robot config's lengths look 1000 times too large: it declares length: m; "
                 "declare units: {length: mm}");
  EXPECT_THAT(r.output, HasSubstr("moves the flange over 2.71e+05 mm at the same joint readings"));
}

TEST_F(BadInput, MillimetresReadAsMetresAreRefusedWhereTheJobIsLoaded) {
  // Where the job is loaded, not only through `run`. Numbers in mm read as m are a thousand
  // times too large: beyond the reader's 100 m for sim_b, so the recording is built in memory.
  WriteJob();
  Recording recording = ReadRecording(testing::Source("tests/data/vsb/sim_b"));
  recording.folder = recording_;
  for (auto& o : recording.observations) o.position_mm *= 1000.0;
  const WorkcellJob job = LoadWorkcellJob(job_, testing::Plugins());
  // A recording that declares m.
  testing::WriteText(
      recording_ + "/recording.yaml",
      ReplaceOnce(ReadText(recording_ + "/recording.yaml"), "length: mm", "length: m"));
  InputError e = testing::CatchInputError([&] { ValidateJobAgainstRecording(job, recording); });
  EXPECT_EQ(FormatLocation(e.where()), recording_ + "/recording.yaml:3:17: ");
  EXPECT_THAT(e.message(), HasSubstr("disagree in size by about 1000 times"));
  EXPECT_EQ(e.hint(),
            "The recording's numbers look like millimetres but recording.yaml "
            "declares length: m: declare units: {length: mm}");
  // An imported recording (always written in mm): the mapping is what to fix.
  testing::WriteText(
      recording_ + "/recording.yaml",
      ReplaceOnce(ReadText(recording_ + "/recording.yaml"), "length: m", "length: mm"));
  testing::WriteText(recording_ + "/import.yaml", "# the mapping it was imported with\n");
  e = testing::CatchInputError([&] { ValidateJobAgainstRecording(job, recording); });
  EXPECT_EQ(FormatLocation(e.where()), recording_ + "/recording.yaml:3:17: ");
  EXPECT_EQ(e.hint(),
            "This recording was imported (its mapping is in import.yaml): the table's "
            "lengths look like millimetres; say units: {length: mm} in the mapping and "
            "import it again");
  // The same recording at its true scale passes.
  for (auto& o : recording.observations) o.position_mm /= 1000.0;
  ValidateJobAgainstRecording(job, recording);
}

TEST_F(BadInput, SimulatingNoPosesIsRefused) {
  std::string sim = ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml"));
  sim = ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml", robot_);
  sim = ReplaceOnce(sim, "random: 150", "random: 0");
  testing::WriteText(dir_ + "/sim.yaml", sim);
  const auto r = testing::RunCellmetry("simulate " + dir_ + "/sim.yaml -o " + dir_ + "/sim");
  EXPECT_EQ(r.exit_code, kInputErrorExitCode) << r.output;
  EXPECT_THAT(r.output, HasSubstr("random: must be between 1 and"));
  EXPECT_FALSE(fs::exists(dir_ + "/sim"));
}

// One broken TARGETS.csv for `cellmetry compensate` (on the unmodified job's result), and the
// error it must produce; no commands file is written.
struct TargetsEdit {
  std::string name;
  std::string text;      // the whole file
  std::string location;  // line:column of the bad cell ("1:" for the header)
  std::string hint;
  std::string message;
};

class BadTargets : public BadInput, public ::testing::WithParamInterface<TargetsEdit> {};

TEST_P(BadTargets, IsRejectedAtItsCell) {
  const TargetsEdit& edit = GetParam();
  WriteJob();
  CopyInTheJobsResult();
  const std::string targets = dir_ + "/targets.csv", commands = dir_ + "/commands.csv";
  testing::WriteText(targets, edit.text);
  const auto r = testing::RunCellmetry("compensate " + output_ + " " + targets + " -o " + commands);
  testing::ExpectOneLineError(r, targets + ":" + edit.location, edit.hint);
  EXPECT_THAT(r.output, HasSubstr(edit.message));
  EXPECT_FALSE(fs::exists(commands));
}

const char kSeed[] = ",q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad";

INSTANTIATE_TEST_SUITE_P(
    Compensate, BadTargets,
    ::testing::Values(
        TargetsEdit{"NonFiniteCoordinate", "id,x_mm,y_mm,z_mm\na,400,nan,-300\n",
                    "2:3:", "replace the value with a measurement",
                    "column 'y_mm': 'nan' is not a finite number"},
        TargetsEdit{"MissingCellInARow", "id,x_mm,y_mm,z_mm\na,400,500,-300\nb,400,500\n",
                    "3:4:", "Fill in a number", "column 'z_mm': empty cell"},
        TargetsEdit{"MissingColumn", "id,x_mm,y_mm\na,400,500\n",
                    "1:", "Give all of x_mm ... z_mm, or none", "missing column 'z_mm'"},
        TargetsEdit{"UnknownColumn", "id,x_mm,y_mm,z_m\na,400,500,-300\n",
                    "1:4:", "Did you mean 'z_mm'?", "unknown column 'z_m'"},
        TargetsEdit{"TextForANumber", "x_mm,y_mm,z_mm,rx_rad,ry_rad,rz_rad\n1,2,3,0,abc,0\n",
                    "2:5:", "Write a plain decimal number",
                    "column 'ry_rad': 'abc' is not a number"},
        TargetsEdit{"HalfASeed",
                    std::string("x_mm,y_mm,z_mm") + kSeed + "\n400,500,-300,1,2,3,,,\n",
                    "2:7:", "on this row, or none", "column 'q4_rad': empty cell"},
        TargetsEdit{"NegativePayload", "x_mm,y_mm,z_mm,payload_kg\n400,500,-300,-1\n",
                    "2:4:", "Give the load at the flange in kg", "a payload cannot be negative"},
        TargetsEdit{"ApproachNotASign",
                    "x_mm,y_mm,z_mm,approach_j1,approach_j2,approach_j3,approach_j4,approach_j5,"
                    "approach_j6\n400,500,-300,1,1,2,1,1,1\n",
                    "2:6:", "Write 1 (the joint moves up into the target)",
                    "an approach direction must be -1, 0 or 1"},
        TargetsEdit{"NoTargetColumns", "id,payload_kg\na,1\n", "1:", "Give x_mm, y_mm, z_mm",
                    "no target columns"}),
    [](const ::testing::TestParamInfo<TargetsEdit>& info) { return info.param.name; });

}  // namespace
}  // namespace cellmetry
