// An interrupted diagnosis resumes (DiagnoseWorkcell with a Checkpoint): the rounds it finished
// are read back, the rest run, and the answer is the one an uninterrupted run gives; a checkpoint
// kept for other inputs is never read.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/formats/checkpoint.h"
#include "support/test_support.h"

namespace cellmetry {
namespace {

class DiagnosisResume : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDirForThisTest("diagnosis_resume");
    std::string sim =
        testing::ReadText(testing::Source("configs/simulations/ur3_physics_base.yaml"));
    sim = testing::ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml",
                               testing::Source("configs/robots/ur3_vsb2020.yaml"));
    sim = testing::ReplaceOnce(sim, "random: 150", "random: 80");
    testing::WriteText(dir_ + "/sim.yaml", sim);
    WorkcellSimulationSpec spec = LoadWorkcellSimulation(dir_ + "/sim.yaml", testing::Plugins());
    testing::ConcealJoint3Compliance(&spec);  // one accepted round, then one refused
    recording_ = SimulateWorkcell(spec, nullptr);
    job_ = testing::Ur3DiagnoseJob(dir_);
  }

  nlohmann::json Diagnose(Checkpoint* checkpoint) {
    const DiagnosisResult d = DiagnoseWorkcell(
        job_.workcell.problem, recording_, testing::JobSolver(job_.workcell),
        JobCandidates(job_, recording_, testing::Plugins()), job_.options, "job.yaml", checkpoint);
    return DiagnosisJson(d);
  }

  std::string dir_;
  Recording recording_;
  DiagnosisJob job_;
};

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// Keeps the checkpoint's first round alone: a run stopped while its second round ran. With
// `mark`, the round's dispersion is changed to it: an answer that shows it was read back.
void KeepFirstRoundOnly(const std::string& path, double mark = 0.0) {
  nlohmann::json pieces = ReadJson(path);
  nlohmann::json first = nlohmann::json::object();
  for (const auto& [key, piece] : pieces.items()) {
    if (key.size() > 8 && key.compare(key.size() - 8, 8, "/round/1") == 0) first[key] = piece;
  }
  if (mark != 0.0) {
    for (auto& [key, piece] : first.items()) piece["round"]["dispersion"] = mark;
  }
  ASSERT_EQ(first.size(), 1u) << pieces.dump(1).substr(0, 400);
  std::ofstream(path) << first.dump(1);
}

TEST_F(DiagnosisResume, StoppedAfterItsFirstRoundGivesTheUninterruptedAnswer) {
  const nlohmann::json uninterrupted = Diagnose(nullptr);
  ASSERT_GE(uninterrupted.at("rounds").size(), 2u) << uninterrupted.dump(1).substr(0, 2000);

  const std::string path = dir_ + "/diagnosis.partial.json";
  Checkpoint kept(path, "inputs");
  EXPECT_EQ(Diagnose(&kept), uninterrupted);
  KeepFirstRoundOnly(path);

  Checkpoint stopped(path, "inputs");
  ASSERT_NE(stopped.Find("round/1"), nullptr);
  ASSERT_EQ(stopped.Find("round/2"), nullptr);
  EXPECT_EQ(Diagnose(&stopped), uninterrupted);
  // The rounds it ran are kept as they finish, beside the one it read back.
  EXPECT_NE(Checkpoint(path, "inputs").Find("round/2"), nullptr);

  // The first round was read, not run again.
  KeepFirstRoundOnly(path, 123.0);
  Checkpoint marked(path, "inputs");
  EXPECT_EQ(Diagnose(&marked).at("rounds").at(0).at("dispersion"), 123.0);
}

TEST_F(DiagnosisResume, ARoundKeptForOtherInputsIsNeverReadBack) {
  const nlohmann::json uninterrupted = Diagnose(nullptr);
  const std::string path = dir_ + "/diagnosis.partial.json";
  {
    Checkpoint other(path, "other inputs");
    Diagnose(&other);
  }
  // The first round of the other inputs, altered: were it read back, the answer would change.
  nlohmann::json pieces = ReadJson(path);
  for (auto& [key, piece] : pieces.items()) {
    if (key == "other inputs/round/1") piece["round"]["accepted"] = "ur3.no_such_effect";
  }
  std::ofstream(path) << pieces.dump(1);
  Checkpoint these(path, "these inputs");
  EXPECT_EQ(these.Find("round/1"), nullptr);
  EXPECT_EQ(Diagnose(&these), uninterrupted);
}

// `cellmetry diagnose` keeps its rounds beside its output while it runs and removes them once the
// output is written: nothing is left over to confuse the next run.
TEST(DiagnoseCommand, LeavesNoCheckpointBehindOnceItsOutputIsWritten) {
  const std::string dir = testing::TempDirForThisTest("diagnose_command");
  const testing::CommandResult run = testing::RunCellmetry(
      "--quiet diagnose " + testing::Source("configs/jobs/vsb_sim_b_diagnose.yaml") + " -o " + dir +
      "/diagnosis");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/diagnosis/diagnosis.json"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/diagnosis.partial.json"));
}

}  // namespace
}  // namespace cellmetry
