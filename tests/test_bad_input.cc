// Bad input through the real command line: every case gets one error line naming the file, the
// line and what to do, exit code 2, and no result folder (not even a partial one).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cellmetry/formats/recording.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

using testing::ReadText;
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
    fs::copy_file(testing::Source("configs/robots/ur3.yaml"), robot_);
  }

  // configs/jobs/vsb_sim_b.yaml with absolute paths; line numbers matter to the tests.
  std::string JobText() const {
    return "job: workcell\n"                                   // 1
           "description: UR3 base + tool offset, VSB sim B\n"  // 2
           "recording: " + recording_ + "\n"                   // 3
           "output: " + output_ + "\n"                         // 4
           "camera_model: static_cameras\n"                    // 5
           "robots:\n"                                         // 6
           "  ur3:\n"                                          // 7
           "    model: " + robot_ + "\n"                       // 8
           "    base: {free: all}\n"                           // 9
           "    tools:\n"                                      // 10
           "      tool: {xyz: [0, 0, 0], free: [x, y, z]}\n"   // 11
           "solver:\n"                                         // 12
           "  type: ceres_lm\n"                                // 13
           "validation:\n"                                     // 14
           "  folds: 5\n";                                     // 15
  }

  void WriteJob(const std::string& text) { testing::WriteText(job_, text); }
  void WriteJob() { WriteJob(JobText()); }

  // Replaces line `line` (1-based) of a recording file.
  void EditLine(const std::string& file, int line, const std::string& replacement) {
    testing::EditLine(recording_ + "/" + file, line, replacement);
  }

  testing::CommandResult Run() { return testing::RunCellmetry("run " + job_); }

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
  WriteJob(ReplaceOnce(JobText(), "model: " + robot_, "model: " + std::string(5000, 'x') + ".yaml"));
  ExpectRejected(Run(), "job.yaml:8:12:", "Give a path relative to the job file");
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
        LineEdit{"NanJointValue", "samples.csv", 5,
                 "3,ur3,3,4.700736523,nan,0.7314307094,4.095294476,5.03745842,0.69",
                 "samples.csv:5:5:", "replace the value with a measurement",
                 "column 'q2': 'nan' is not a finite number"},
        LineEdit{"SampleWithTooFewJoints", "samples.csv", 5,
                 "3,ur3,3,4.700736523,3.39327383,0.7314307094,4.095294476,5.03745842",
                 "samples.csv:5:9:", "Give one joint value per joint",
                 "robot 'ur3' has 6 joints but this sample has no q6"},
        LineEdit{"ObservationOfAnUnknownCamera", "observations.csv", 4,
                 "1,cam9,tool,244.702809,-55.417908,725.561068,-2.15,1.60,0.53",
                 "observations.csv:4:2:", "List it under 'cameras' in recording.yaml",
                 "unknown camera 'cam9'"},
        LineEdit{"ObservationOfAnUnknownTarget", "observations.csv", 4,
                 "1,cam1,tool2,244.702809,-55.417908,725.561068,-2.15,1.60,0.53",
                 "observations.csv:4:3:", "List it under 'targets' in recording.yaml",
                 "unknown target 'tool2'"},
        LineEdit{"HugePositionOfAnObservation", "observations.csv", 4,
                 "1,cam1,tool,1e300,-55.417908,725.561068,-2.15,1.60,0.53",
                 "observations.csv:4:4:", "check the units declared in recording.yaml",
                 "is beyond any measurement of it"},
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
  EXPECT_THAT(r.output, HasSubstr("Known solver types: ceres_lm, gradient_descent, jacobian_pinv, nlopt"));
}

TEST_F(BadInput, UnknownRobotModelTypeListsTheKnownOnes) {
  WriteJob();
  testing::WriteText(robot_, ReplaceOnce(ReadText(robot_), "type: serial_mdh", "type: serial_mdhh"));
  const auto r = Run();
  ExpectRejected(r, "ur3.yaml:4:7:", "Did you mean 'serial_mdh'?");
  EXPECT_THAT(r.output, HasSubstr("unknown robot model type 'serial_mdhh'"));
  EXPECT_THAT(r.output, HasSubstr("Known robot model types: delta, serial_mdh"));
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
        JobEdit{"OneFold", "folds: 5", "folds: 1", "job.yaml:15:10:",
                "0 turns cross-validation off", "one fold holds nothing out"},
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
                "noise: {cameras: {cam9: {position_mm: [0.1, 0.1, 0.4]}}}\n", "job.yaml:16:25:",
                "Name the cameras as recording.yaml does",
                "camera 'cam9' under noise: is not in the recording"},
        JobEdit{"NegativeIdentifiabilityTolerance", "", "identifiability_tolerance: -1\n",
                "job.yaml:16:28:", "1e-8 is the default",
                "identifiability_tolerance: must be between"},
        JobEdit{"VifBelowOne", "", "weak_vif: 0.5\n", "job.yaml:16:11:", "at least 1",
                "weak_vif: must be between 1 and"},
        JobEdit{"MissingPluginFolder", "", "plugin_paths: [/nonexistent/cellmetry/plugins]\n",
                "job.yaml:16:16:", "Point plugin_paths at the folder",
                "no plugin folder at '/nonexistent/cellmetry/plugins'"},
        JobEdit{"DuplicateKey", "", "validation:\n  folds: 3\n", "job.yaml:16:1:",
                "Keep one of them", "key 'validation' appears twice in this map"},
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
  testing::WriteText(recording_ + "/recording.yaml",
                     ReplaceOnce(ReadText(recording_ + "/recording.yaml"), "length: mm", "length: m"));
  InputError e = testing::CatchInputError([&] { ValidateJobAgainstRecording(job, recording); });
  EXPECT_EQ(FormatLocation(e.where()), recording_ + "/recording.yaml:3:17: ");
  EXPECT_THAT(e.message(), HasSubstr("disagree in size by about 1000 times"));
  EXPECT_EQ(e.hint(), "The recording's numbers look like millimetres but recording.yaml "
                      "declares length: m: declare units: {length: mm}");
  // An imported recording (always written in mm): the mapping is what to fix.
  testing::WriteText(recording_ + "/recording.yaml",
                     ReplaceOnce(ReadText(recording_ + "/recording.yaml"), "length: m", "length: mm"));
  testing::WriteText(recording_ + "/import.yaml", "# the mapping it was imported with\n");
  e = testing::CatchInputError([&] { ValidateJobAgainstRecording(job, recording); });
  EXPECT_EQ(FormatLocation(e.where()), recording_ + "/recording.yaml:3:17: ");
  EXPECT_EQ(e.hint(), "This recording was imported (its mapping is in import.yaml): the table's "
                      "lengths look like millimetres; say units: {length: mm} in the mapping and "
                      "import it again");
  // The same recording at its true scale passes.
  for (auto& o : recording.observations) o.position_mm /= 1000.0;
  ValidateJobAgainstRecording(job, recording);
}

TEST_F(BadInput, SimulatingNoPosesIsRefused) {
  std::string sim = ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml"));
  sim = ReplaceOnce(sim, "../robots/ur3.yaml", robot_);
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
  ASSERT_EQ(Run().exit_code, 0);
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
        TargetsEdit{"NonFiniteCoordinate", "id,x_mm,y_mm,z_mm\na,400,nan,-300\n", "2:3:",
                    "replace the value with a measurement",
                    "column 'y_mm': 'nan' is not a finite number"},
        TargetsEdit{"MissingCellInARow", "id,x_mm,y_mm,z_mm\na,400,500,-300\nb,400,500\n",
                    "3:4:", "Fill in a number", "column 'z_mm': empty cell"},
        TargetsEdit{"MissingColumn", "id,x_mm,y_mm\na,400,500\n", "1:",
                    "Give all of x_mm ... z_mm, or none", "missing column 'z_mm'"},
        TargetsEdit{"UnknownColumn", "id,x_mm,y_mm,z_m\na,400,500,-300\n", "1:4:",
                    "Did you mean 'z_mm'?", "unknown column 'z_m'"},
        TargetsEdit{"TextForANumber", "x_mm,y_mm,z_mm,rx_rad,ry_rad,rz_rad\n1,2,3,0,abc,0\n",
                    "2:5:", "Write a plain decimal number", "column 'ry_rad': 'abc' is not a number"},
        TargetsEdit{"HalfASeed",
                    std::string("x_mm,y_mm,z_mm") + kSeed + "\n400,500,-300,1,2,3,,,\n", "2:7:",
                    "on this row, or none", "column 'q4_rad': empty cell"},
        TargetsEdit{"NegativePayload", "x_mm,y_mm,z_mm,payload_kg\n400,500,-300,-1\n", "2:4:",
                    "Give the load at the flange in kg", "a payload cannot be negative"},
        TargetsEdit{"ApproachNotASign",
                    "x_mm,y_mm,z_mm,approach_j1,approach_j2,approach_j3,approach_j4,approach_j5,"
                    "approach_j6\n400,500,-300,1,1,2,1,1,1\n", "2:6:",
                    "Write 1 (the joint moves up into the target)",
                    "an approach direction must be -1, 0 or 1"},
        TargetsEdit{"NoTargetColumns", "id,payload_kg\na,1\n", "1:",
                    "Give x_mm, y_mm, z_mm", "no target columns"}),
    [](const ::testing::TestParamInfo<TargetsEdit>& info) { return info.param.name; });

}  // namespace
}  // namespace cellmetry
