// Nothing lost: cellmetry replaces only what it wrote itself. Through the real command line, a
// job or simulation whose output names a user's file, a user's folder, the job's own recording
// or the working directory is refused (exit 2, the path named) before any work, and the path is
// left exactly as it was; a result folder cellmetry wrote is replaced by the next run and kept
// recoverable beside it as <output>.previous; staging
// folders a killed run left behind are cleared by the next run.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "cellmetry/formats/atomic_file.h"
#include "support/test_support.h"

namespace fs = std::filesystem;

namespace cellmetry {
namespace {

using ::testing::HasSubstr;

class OutputSafety : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDirForThisTest("output_safety");
    recording_ = dir_ + "/sim_b";
    fs::copy(testing::Source("tests/data/vsb/sim_b"), recording_);
  }

  // configs/jobs/vsb_sim_b.yaml with absolute paths and `output`.
  void WriteJob(const std::string& output) {
    testing::WriteText(
        dir_ + "/job.yaml",
        "job: workcell\nrecording: " + recording_ + "\noutput: " + output +
            "\nrobots:\n  ur3:\n    model: " + testing::Source("configs/robots/ur3_vsb2020.yaml") +
            "\n    base: {free: all}\n    tools:\n      tool: {free: [x, y, z]}\n"
            "solver: {type: ceres_lm}\nvalidation: {folds: 0}\n");
  }

  testing::CommandResult Run() { return testing::RunCellmetry("run " + dir_ + "/job.yaml"); }

  std::string dir_, recording_;
};

TEST_F(OutputSafety, AUsersFileIsNotReplaced) {
  testing::WriteText(dir_ + "/notes.txt", "my notes\n");
  WriteJob(dir_ + "/notes.txt");
  const auto r = Run();
  EXPECT_EQ(r.exit_code, kInputErrorExitCode) << r.output;
  EXPECT_THAT(r.output, HasSubstr("notes.txt: error: the output path is an existing file"));
  EXPECT_EQ(testing::ReadText(dir_ + "/notes.txt"), "my notes\n");
}

TEST_F(OutputSafety, AUsersFolderIsNotReplaced) {
  testing::WriteText(dir_ + "/mine/data.csv", "1,2,3\n");
  WriteJob(dir_ + "/mine");
  const auto r = Run();
  EXPECT_EQ(r.exit_code, kInputErrorExitCode) << r.output;
  EXPECT_THAT(r.output, HasSubstr("was not written by cellmetry"));
  EXPECT_EQ(testing::ReadText(dir_ + "/mine/data.csv"), "1,2,3\n");
}

TEST_F(OutputSafety, TheJobsOwnRecordingIsNotReplaced) {
  WriteJob(recording_);
  const auto r = Run();
  EXPECT_EQ(r.exit_code, kInputErrorExitCode) << r.output;
  EXPECT_TRUE(fs::exists(recording_ + "/observations.csv"));
  // A recording cellmetry simulated is its output too, but of another kind: still refused.
  const auto sim = testing::RunCellmetry(
      "simulate " + testing::Source("configs/simulations/ur3_two_cameras.yaml") + " -o " + dir_ +
      "/simulated");
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  WriteJob(dir_ + "/simulated");
  const auto again = Run();
  EXPECT_EQ(again.exit_code, kInputErrorExitCode) << again.output;
  EXPECT_THAT(again.output, HasSubstr("holds a cellmetry recording, which a result would replace"));
  EXPECT_TRUE(fs::exists(dir_ + "/simulated/observations.csv"));
}

TEST_F(OutputSafety, SimulateDoesNotOverwriteARecordingItDidNotWrite) {
  const auto r = testing::RunCellmetry("simulate " +
                                       testing::Source("configs/simulations/ur3_two_cameras.yaml") +
                                       " -o " + recording_);
  EXPECT_EQ(r.exit_code, kInputErrorExitCode) << r.output;
  EXPECT_EQ(testing::ReadText(recording_ + "/observations.csv"),
            testing::ReadText(testing::Source("tests/data/vsb/sim_b/observations.csv")));
}

TEST_F(OutputSafety, ItsOwnResultIsReplacedAndStaleStagingCleared) {
  WriteJob(dir_ + "/result");
  ASSERT_EQ(Run().exit_code, 0);
  ASSERT_TRUE(fs::exists(dir_ + "/result/" + std::string(kOutputMarker)));
  // A run killed while writing left its staging folder (process 999999 is not running).
  testing::WriteText(dir_ + "/result.partial999999/result.yaml", "half\n");
  // A file the run wrote, marked to be told apart from the next run's.
  testing::WriteText(dir_ + "/result/residuals.csv", "from the first run\n");
  const auto r = Run();
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ + "/result/result.json"));
  EXPECT_FALSE(fs::exists(dir_ + "/result.partial999999"));
  // The replaced result is recoverable beside the new one, one generation deep.
  EXPECT_EQ(testing::ReadText(dir_ + "/result.previous/residuals.csv"), "from the first run\n");
  EXPECT_NE(testing::ReadText(dir_ + "/result/residuals.csv"), "from the first run\n");
  ASSERT_EQ(Run().exit_code, 0);
  EXPECT_NE(testing::ReadText(dir_ + "/result.previous/residuals.csv"), "from the first run\n");
  EXPECT_TRUE(fs::exists(dir_ + "/result.previous/result.json"));
}

// A user's notes or photos put into a result folder went to result.previous at the next run
// and were deleted at the one after. The folder is now refused as an output while they are in
// it, the files named, and nothing is moved; once they are taken out, the run replaces it.
TEST_F(OutputSafety, AUsersFilesInAResultFolderAreNeverMovedAside) {
  WriteJob(dir_ + "/result");
  ASSERT_EQ(Run().exit_code, 0);
  const std::string result_json = testing::ReadText(dir_ + "/result/result.json");
  testing::WriteText(dir_ + "/result/my_notes.txt", "base looks 2 mm high\n");
  const auto notes = Run();
  EXPECT_EQ(notes.exit_code, kInputErrorExitCode) << notes.output;
  EXPECT_THAT(notes.output, HasSubstr("the output folder holds 'my_notes.txt', which cellmetry "
                                      "did not write"));
  EXPECT_THAT(notes.output, HasSubstr("Move 'my_notes.txt' out of the folder"));
  EXPECT_EQ(testing::ReadText(dir_ + "/result/my_notes.txt"), "base looks 2 mm high\n");
  EXPECT_EQ(testing::ReadText(dir_ + "/result/result.json"), result_json);
  EXPECT_FALSE(fs::exists(dir_ + "/result.previous"));

  fs::rename(dir_ + "/result/my_notes.txt", dir_ + "/my_notes.txt");
  testing::WriteText(dir_ + "/result/photos/cell.jpg", "jpeg\n");
  const auto photos = Run();
  EXPECT_EQ(photos.exit_code, kInputErrorExitCode) << photos.output;
  EXPECT_THAT(photos.output, HasSubstr("holds 'photos'"));
  EXPECT_EQ(testing::ReadText(dir_ + "/result/photos/cell.jpg"), "jpeg\n");

  fs::rename(dir_ + "/result/photos", dir_ + "/photos");
  const auto again = Run();
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_TRUE(fs::exists(dir_ + "/result.previous/result.json"));
  // In the slot the replaced result went to, a user's file is refused the same way.
  testing::WriteText(dir_ + "/result.previous/my_notes.txt", "mine\n");
  const auto slot = Run();
  EXPECT_EQ(slot.exit_code, kInputErrorExitCode) << slot.output;
  EXPECT_THAT(slot.output, HasSubstr("result.previous: error: the output folder holds "
                                     "'my_notes.txt'"));
  EXPECT_EQ(testing::ReadText(dir_ + "/result.previous/my_notes.txt"), "mine\n");
}

// A folder of cellmetry's own inside a result (`diagnose` writes <output>/diagnosis by default)
// is not a user's file: the result is replaced with it, as before.
TEST_F(OutputSafety, ADiagnosisInsideAResultIsCellmetrysOwn) {
  WriteJob(dir_ + "/result");
  ASSERT_EQ(Run().exit_code, 0);
  testing::WriteText(dir_ + "/result/diagnosis/" + std::string(kOutputMarker), "kind: diagnosis\n");
  testing::WriteText(dir_ + "/result/diagnosis/report.txt", "a diagnosis\n");
  const auto r = Run();
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(testing::ReadText(dir_ + "/result.previous/diagnosis/report.txt"), "a diagnosis\n");
}

// A recording `simulate` wrote and `detect` then added its files to is replaced by the next
// `simulate` whole: detect's files are listed in the folder's marker as cellmetry's own.
TEST_F(OutputSafety, FilesAddedByALaterCommandAreListedAsCellmetrys) {
  const std::string sim = testing::Source("configs/simulations/ur3_two_cameras.yaml");
  ASSERT_EQ(testing::RunCellmetry("simulate " + sim + " -o " + dir_ + "/simulated").exit_code, 0);
  testing::WriteText(dir_ + "/simulated/detections.jsonl", "");
  NoteOutputFile(dir_ + "/simulated", "detections.jsonl");
  const auto r = testing::RunCellmetry("simulate " + sim + " -o " + dir_ + "/simulated");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ + "/simulated.previous/detections.jsonl"));
}

TEST_F(OutputSafety, APreviousSlotHoldingAUsersFolderIsNotReplaced) {
  WriteJob(dir_ + "/result");
  ASSERT_EQ(Run().exit_code, 0);
  testing::WriteText(dir_ + "/result.previous/mine.txt", "mine\n");
  const auto r = Run();
  EXPECT_EQ(r.exit_code, kInputErrorExitCode) << r.output;
  EXPECT_EQ(testing::ReadText(dir_ + "/result.previous/mine.txt"), "mine\n");
  EXPECT_TRUE(fs::exists(dir_ + "/result/result.json"));
}

TEST(OutputFolder, TheWorkingDirectoryIsNeverReplaced) {
  const std::string here = fs::current_path().string();
  try {
    CheckReplaceable(".", "result");
    FAIL() << "the working directory was accepted as an output folder";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("holds the working directory"));
  }
  EXPECT_EQ(fs::current_path().string(), here);
}

}  // namespace
}  // namespace cellmetry
