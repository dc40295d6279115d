#include "support/test_support.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cellmetry/basics/progress.h"
#include "cellmetry/formats/recording.h"

namespace fs = std::filesystem;

namespace cellmetry::testing {

Registry& Plugins() {
  static bool loaded = [] {
    Progress::SetQuiet(true);
    Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
    return true;
  }();
  (void)loaded;
  return Registry::Global();
}

std::string Source(const std::string& relative) {
  return std::string(CELLMETRY_SOURCE_DIR) + "/" + relative;
}

std::string TempDir(const std::string& name) {
  const fs::path dir = fs::path(CELLMETRY_BUILD_DIR) / "test_tmp" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::string TempDirForThisTest(const std::string& folder) {
  return TempDir(folder + "/" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
}

void WriteText(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string ReplaceOnce(const std::string& text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not found";
  if (at == std::string::npos) return text;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << "'" << from << "' found twice";
  return text.substr(0, at) + to + text.substr(at + from.size());
}

void EditLine(const std::string& path, int line, const std::string& replacement) {
  std::istringstream in(ReadText(path));
  std::string text, current;
  for (int n = 1; std::getline(in, current); ++n)
    text += (n == line ? replacement : current) + "\n";
  WriteText(path, text);
}

CommandResult RunCellmetry(const std::string& arguments) {
  const std::string command = std::string(CELLMETRY_BINARY) + " -q " + arguments + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

void ExpectOneLineError(const CommandResult& result, const std::string& location,
                        const std::string& text) {
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(location + " error: "), std::string::npos)
      << "expected '" << location << " error: ' in: " << result.output;
  EXPECT_NE(result.output.find(text), std::string::npos)
      << "expected '" << text << "' in: " << result.output;
  std::istringstream lines(result.output);
  int non_empty = 0;
  for (std::string line; std::getline(lines, line);) non_empty += !line.empty();
  EXPECT_EQ(non_empty, 1) << result.output;
}

SolverMaker JobSolver(const WorkcellJob& job) {
  return [&job] { return Plugins().CreateSolver(job.solver_type, *job.solver_config); };
}

WorkcellResult Identify(const WorkcellJob& job, const Recording& recording) {
  return IdentifyWorkcell(job.problem, recording, JobSolver(job));
}

const FrameEstimate& Frame(const WorkcellResult& result, const std::string& name) {
  for (const auto& f : result.frames) {
    if (f.name == name) return f;
  }
  throw std::runtime_error("no frame " + name);
}

const char kTwoCameraNoiseYaml[] =
    "noise: {cameras: {cam1: {position_mm: [0.1, 0.1, 0.4], rotation_rad: [0.0005, 0.0005, "
    "0.001]}, cam2: {position_mm: [0.1, 0.1, 0.4], rotation_rad: [0.0005, 0.0005, 0.001]}}}\n";

WorkcellSimulationSpec SimulateScaledToolBoard(const std::string& dir, double scale) {
  std::string sim = ReadText(Source("configs/simulations/ur3_two_cameras.yaml"));
  sim = ReplaceOnce(sim, "../robots/ur3_vsb2020.yaml", Source("configs/robots/ur3_vsb2020.yaml"));
  sim = ReplaceOnce(sim, "../../tests/data/vsb/sim_b", Source("tests/data/vsb/sim_b"));
  WriteText(dir + "/sim.yaml", sim);
  WorkcellSimulationSpec spec = LoadWorkcellSimulation(dir + "/sim.yaml", Plugins());
  spec.sigma_position_mm.setZero();
  spec.sigma_rotation_rad.setZero();
  const ConfigNode config = ConfigNode::LoadString("{type: target_scale, targets: [tool]}", "test");
  SimulatedEffect board;
  board.name = "camera.target_scale";
  board.effect = Plugins().CreateEffect("target_scale", config, *spec.robots[0].model);
  board.values = {scale};
  spec.measurement_effects.push_back(board);
  WriteRecording(SimulateWorkcell(spec, nullptr), dir + "/rec", "");
  return spec;
}

void ConcealJoint3Compliance(WorkcellSimulationSpec* spec, double compliance) {
  ConcealJointCompliance(spec, 3, compliance);
}

void ConcealJointCompliance(WorkcellSimulationSpec* spec, int joint, double compliance) {
  SimulatedEffect e;
  e.name = "ur3.joint_compliance";
  e.effect = Plugins().CreateEffect(
      "joint_compliance",
      ConfigNode::LoadString("{type: joint_compliance, joints: [" + std::to_string(joint) +
                                 "], link_masses_kg: [2.0, 3.42, 1.26, 0.8, 0.8, 0.35]}",
                             "test"),
      *spec->robots[0].model);
  e.values = {compliance};
  spec->robots[0].effects.push_back(e);
}

DiagnosisJob Ur3DiagnoseJob(const std::string& dir) {
  const std::string job = ReplaceOnce(ReadText(Source("configs/jobs/ur3_diagnose.yaml")),
                                      "model: ../robots/ur3_vsb2020.yaml",
                                      "model: " + Source("configs/robots/ur3_vsb2020.yaml"));
  WriteText(dir + "/job.yaml", job);
  DiagnosisJob loaded = LoadDiagnosisJob(dir + "/job.yaml", Plugins(), false);
  loaded.options.bootstrap = 30;
  return loaded;
}

DiagnosisResult Diagnose(const DiagnosisJob& job, const Recording& recording,
                         const std::string& origin) {
  return DiagnoseWorkcell(job.workcell.problem, recording, JobSolver(job.workcell),
                          JobCandidates(job, recording, Plugins()), job.options, origin);
}

PosePlan Plan(const DiagnosisJob& job, const Recording& recording, const PosePlanOptions& options) {
  WorkcellProblem problem = job.workcell.problem;
  problem.folds = 0;
  const WorkcellResult fitted = IdentifyWorkcell(problem, recording, JobSolver(job.workcell));
  return PlanPoses(problem, recording, fitted, JobCandidates(job, recording, Plugins()), options);
}

}  // namespace cellmetry::testing
