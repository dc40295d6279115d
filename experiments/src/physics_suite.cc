#include "cellmetry/experiments/physics_suite.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/cell/workcell_simulation.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/experiments/concealed_physics.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/fixed_number.h"

namespace cellmetry {
namespace {

constexpr double kTrialMagnitude = 1e-5;  // small enough for the linear regime

WorkcellSimulationSpec CaseSimulation(const WorkcellSimulationSpec& base, const SuiteCase& c,
                                      double magnitude, unsigned seed, bool noise,
                                      Registry& registry) {
  WorkcellSimulationSpec spec = base;
  spec.seed = seed;
  spec.noise_seed = seed;  // the recording's noise is drawn from this one (workcell_simulation.h)
  if (!noise) {
    spec.sigma_position_mm.setZero();
    spec.sigma_rotation_rad.setZero();
  }
  SimulatedRobot& robot = spec.robots.front();
  if (c.effect) {
    SimulatedEffect e;
    const std::string type = (*c.effect)["type"].AsString();
    e.effect = registry.CreateEffect(type, *c.effect, *robot.model);
    e.values.assign(e.effect->parameters().size(), magnitude);
    const bool measurement = e.effect->stage() == EffectStage::kMeasurement;
    e.name = (measurement ? std::string("camera") : robot.name) + "." + type;
    (measurement ? spec.measurement_effects : robot.effects).push_back(e);
  }
  if (c.concealed) {
    ConcealedPhysics physics = ReadConcealedPhysics(*c.concealed);
    physics.magnitude = magnitude;
    if (physics.robot.empty() && physics.kind != "camera_bump") physics.robot = robot.name;
    spec.concealed.push_back(std::make_shared<ConcealedPhysics>(physics));
  }
  return spec;
}

SolverMaker MakerOf(const WorkcellJob& job, Registry& registry) {
  return [&job, &registry] { return registry.CreateSolver(job.solver_type, *job.solver_config); };
}

// The job's problem whitened by the simulation's own noise: a noise-free recording has no
// scatter to estimate it from.
WorkcellProblem WhitenedBySimulation(const DiagnosisJob& job, const WorkcellSimulationSpec& base) {
  WorkcellProblem problem = job.workcell.problem;
  for (const auto& [camera, pose] : base.T_world_cam) {
    problem.noise.position_sigma_mm[camera] = base.sigma_position_mm;
    problem.noise.rotation_sigma_rad[camera] = base.sigma_rotation_rad;
  }
  return problem;
}

// The effect size at which the part of the case's physics the geometry cannot absorb has
// whitened norm `snr` (noise-free simulation, geometric fit, linear scaling).
double MagnitudeForSnr(const PhysicsSuiteSpec& suite, const WorkcellSimulationSpec& base,
                       const DiagnosisJob& job, const SuiteCase& c, Registry& registry) {
  const WorkcellSimulationSpec spec = CaseSimulation(base, c, kTrialMagnitude, 1, false, registry);
  const Recording recording = SimulateWorkcell(spec, nullptr);
  WorkcellProblem problem = WhitenedBySimulation(job, base);
  problem.folds = 0;
  problem.leave_one_camera_out = false;
  // Every observation counts: the outlier test would leave out the views a lens's distortion
  // moves most (eight of the UR3's at this size), and the norm of the rest is not the signal
  // the finder's candidates are scored on (its linearization has every row).
  problem.outlier_test = OutlierTest::kOff;
  const WorkcellResult fit = IdentifyWorkcell(problem, recording, MakerOf(job.workcell, registry));
  double chi2 = 0.0;
  for (const auto& row : fit.residuals) chi2 += row.normalized.squaredNorm();
  if (!(chi2 > 0)) return 0.0;
  return kTrialMagnitude * suite.snr / std::sqrt(chi2);
}

// The oracle's Bayes choice on the case's noise-free recording at its size (seed 1's poses).
OracleSelection CaseOracle(const WorkcellSimulationSpec& base, const DiagnosisJob& job,
                           const SuiteCase& c, double magnitude, Registry& registry) {
  const WorkcellSimulationSpec spec = CaseSimulation(base, c, magnitude, 1, false, registry);
  const Recording recording = SimulateWorkcell(spec, nullptr);
  return DrawOracleSelections(
      WhitenedBySimulation(job, base), recording, MakerOf(job.workcell, registry),
      JobCandidates(job, recording, registry), c.expect, job.options, OracleSelectionOptions{});
}

// The tests the round's chosen candidate failed, for the misses column.
std::string FailedTests(const CandidateFinding& f) {
  std::string failed = f.name + ":";
  for (const auto& test : f.failed) {
    failed += " " + test;
    if (test == "bootstrap") {
      failed += " " + FixedNumber(f.bootstrap_share, 2);
      if (!f.bootstrap_rival.empty()) failed += " vs " + f.bootstrap_rival;
    }
    if (test == "rivals") failed += " " + FixedNumber(f.rival_p, 3) + " vs " + f.rival;
  }
  if (!f.look_alikes.empty()) {
    failed += " (like " + f.look_alikes.front().label + ", " +
              FixedNumber(f.look_alikes.front().correlation, 2) + ")";
  }
  return failed;
}

// A case's size for the suite's SNR and the oracle's choice at it: what every seed shares.
SuiteCaseResult SetUpCase(const PhysicsSuiteSpec& suite, const SuiteCell& cell,
                          const WorkcellSimulationSpec& base, const DiagnosisJob& job,
                          const SuiteCase& c, Registry& registry) {
  SuiteCaseResult result;
  result.cell = cell.name;
  result.spec = c;
  const bool has_physics = c.effect || c.concealed;
  result.magnitude = has_physics ? MagnitudeForSnr(suite, base, job, c, registry) : 0.0;
  if (has_physics && c.expect != "unexplained" && result.magnitude > 0) {
    result.oracle = CaseOracle(base, job, c, result.magnitude, registry);
  }
  return result;
}

// One seed of a case: a recording simulated with its hidden physics, diagnosed.
SuiteRun RunSeed(const SuiteCell& cell, const WorkcellSimulationSpec& base, const DiagnosisJob& job,
                 const SuiteCaseResult& set_up, int seed, Registry& registry) {
  const auto start = std::chrono::steady_clock::now();
  const WorkcellSimulationSpec spec =
      CaseSimulation(base, set_up.spec, set_up.magnitude, 1000u + seed, true, registry);
  const Recording recording = SimulateWorkcell(spec, nullptr);
  WorkcellProblem problem = job.workcell.problem;
  problem.leave_one_camera_out = false;  // the suite scores names, not each camera
  const DiagnosisResult d =
      DiagnoseWorkcell(problem, recording, MakerOf(job.workcell, registry),
                       JobCandidates(job, recording, registry), job.options, cell.job);
  SuiteRun run;
  run.named = !d.accepted.empty()      ? d.accepted.front().name
              : !d.unexplained.empty() ? "unexplained"
                                       : "none";
  if (!d.accepted.empty()) {
    run.aliases = d.accepted.front().alias_names;
    run.group = d.accepted.front().group;
  }
  if (d.accepted.empty()) run.tied = TiedCandidates(d);
  run.held_out_over_floor = d.final.held_out_rms_mm / d.floor_rms_mm;
  for (const auto& f :
       d.rounds.empty() ? std::vector<CandidateFinding>{} : d.rounds.back().candidates) {
    if (!f.failed.empty()) run.failed = FailedTests(f);
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

// The checkpoint of each case's finished seeds (<output>.partial.json), keyed so that a changed
// suite does not reuse stale cases.
std::string CheckpointPath(const PhysicsSuiteSpec& suite) { return suite.output + ".partial.json"; }

std::string CaseKey(const PhysicsSuiteSpec& suite, const SuiteCell& cell, const SuiteCase& c) {
  return cell.name + "/" + c.name + "/" + std::to_string(suite.seeds) + "/" +
         FixedNumber(suite.snr, 3);
}

nlohmann::json ToJson(const SuiteCaseResult& r) {
  nlohmann::json runs = nlohmann::json::array();
  for (const auto& run : r.runs) {
    runs.push_back({{"named", run.named},
                    {"aliases", run.aliases},
                    {"group", run.group},
                    {"failed", run.failed},
                    {"tied", run.tied},
                    {"held_out_over_floor", run.held_out_over_floor},
                    {"seconds", run.seconds}});
  }
  const OracleSelection& o = r.oracle;
  return {{"magnitude", r.magnitude},
          {"runs", runs},
          {"oracle",
           {{"mismatch_norm", o.mismatch_norm},
            {"testable", o.testable},
            {"right_candidates", o.right_candidates},
            {"right_by_posterior", o.right_by_posterior},
            {"wrong_by_posterior", o.wrong_by_posterior}}}};
}

SuiteCaseResult FromJson(const nlohmann::json& j, const std::string& cell, const SuiteCase& c) {
  SuiteCaseResult r;
  r.cell = cell;
  r.spec = c;
  r.magnitude = j.at("magnitude").get<double>();
  for (const auto& run : j.at("runs")) {
    SuiteRun read{run.at("named").get<std::string>(),
                  run.at("failed").get<std::string>(),
                  run.at("held_out_over_floor").get<double>(),
                  run.at("seconds").get<double>(),
                  {},
                  ""};
    if (run.contains("aliases")) read.aliases = run.at("aliases").get<std::vector<std::string>>();
    if (run.contains("group")) read.group = run.at("group").get<std::string>();
    if (run.contains("tied")) read.tied = run.at("tied").get<std::vector<std::string>>();
    r.runs.push_back(read);
  }
  if (j.contains("oracle")) {
    const auto& o = j.at("oracle");
    r.oracle.mismatch_norm = o.at("mismatch_norm").get<double>();
    r.oracle.testable = o.at("testable").get<int>();
    r.oracle.right_candidates = o.at("right_candidates").get<int>();
    r.oracle.right_by_posterior = o.at("right_by_posterior").get<std::vector<int>>();
    r.oracle.wrong_by_posterior = o.at("wrong_by_posterior").get<std::vector<int>>();
  }
  return r;
}

nlohmann::json ReadCheckpoint(const PhysicsSuiteSpec& suite) {
  std::ifstream in(CheckpointPath(suite));
  if (!in) return nlohmann::json::object();
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nlohmann::json::object();  // a torn file from an old crash: start over
  }
}

// Whether a run named what its case expected: nothing claimed for "none", the expected name or
// a nested variant of it ("ur3.transmission_j4" is named by its harmonics' candidates too), as
// the finding's name or one of its exact aliases (one finding with two names: a camera's depth
// scale along the ray and its focal length, for targets near the optical axis), or the finding's
// group where the case expects a group (a richer lens: "camera.calibration_cam2", which the
// library describes by its pieces).
bool IsRight(const SuiteCase& c, const SuiteRun& run) {
  const bool claimed = run.named != "none" && run.named != "unexplained";
  if (c.expect == "none") return !claimed;
  if (run.named.rfind(c.expect, 0) == 0) return true;
  if (claimed && !run.group.empty() && run.group == c.expect) return true;
  return claimed && std::any_of(run.aliases.begin(), run.aliases.end(),
                                [&](const auto& a) { return a.rfind(c.expect, 0) == 0; });
}

}  // namespace

bool SuiteCaseResult::named_right(const SuiteRun& run) const { return IsRight(spec, run); }

int SuiteCaseResult::right() const {
  int n = 0;
  for (const auto& r : runs) n += IsRight(spec, r);
  return n;
}

PhysicsSuiteSpec LoadPhysicsSuite(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"compare", "description", "seeds", "snr", "cells", "output"});
  PhysicsSuiteSpec spec;
  spec.file = path;
  spec.seeds = root.GetInt("seeds", spec.seeds);
  spec.snr = root.GetDouble("snr", spec.snr);
  if (spec.seeds < 1) throw root["seeds"].Error("needs at least 1 run per case");
  if (!(spec.snr > 0)) throw root["snr"].Error("must be positive", "6 is the issue's bar");
  spec.output = root.ResolvePath(root.GetString("output", "../../results/physics_suite.md"));
  for (const auto& cell_node : root["cells"].Elements()) {
    cell_node.ExpectKeys({"name", "simulation", "job", "cases"});
    SuiteCell cell;
    cell.name = cell_node["name"].AsString();
    cell.simulation = cell_node.ResolvePath(cell_node["simulation"].AsString());
    cell.job = cell_node.ResolvePath(cell_node["job"].AsString());
    for (const auto& node : cell_node["cases"].Elements()) {
      node.ExpectKeys({"name", "expect", "effect", "concealed"});
      SuiteCase c;
      c.name = node["name"].AsString();
      c.expect = node["expect"].AsString();
      if (node.Has("effect")) c.effect = node["effect"];
      if (node.Has("concealed")) c.concealed = node["concealed"];
      if (c.effect && c.concealed) throw node.Error("give effect: or concealed:, not both");
      cell.cases.push_back(c);
    }
    if (cell.cases.empty()) {
      throw cell_node["cases"].Error("lists no case: the cell would add nothing to the table",
                                     "Give at least one case, or remove the cell");
    }
    spec.cells.push_back(cell);
  }
  if (spec.cells.empty()) throw root["cells"].Error("lists no cell");
  return spec;
}

std::vector<SuiteCaseResult> RunPhysicsSuite(const PhysicsSuiteSpec& suite, Registry& registry) {
  struct CaseState {
    const SuiteCell* cell;
    const SuiteCase* c;
    size_t cell_index;
    std::string key;
    std::optional<SuiteCaseResult> result;  // once set up: its size, oracle and seeds run
  };
  std::vector<WorkcellSimulationSpec> bases;
  std::vector<DiagnosisJob> jobs;
  std::vector<CaseState> cases;
  const nlohmann::json kept = ReadCheckpoint(suite);
  int resumed = 0;
  for (const auto& cell : suite.cells) {
    bases.push_back(LoadWorkcellSimulation(cell.simulation, registry, ReadConcealedDisturbance));
    jobs.push_back(LoadDiagnosisJob(cell.job, registry, /*recording_must_exist=*/false));
    for (const auto& c : cell.cases) {
      CaseState state{&cell, &c, bases.size() - 1, CaseKey(suite, cell, c), std::nullopt};
      if (kept.contains(state.key)) {
        state.result = FromJson(kept[state.key], cell.name, c);
        resumed += static_cast<int>(state.result->runs.size());
      }
      cases.push_back(std::move(state));
    }
  }
  Progress progress("physics suite runs", static_cast<int>(cases.size()) * suite.seeds);
  if (resumed > 0) Progress::Note("resuming: " + std::to_string(resumed) + " runs done before");
  progress.Resume(resumed);
  nlohmann::json done = kept;
  // Seed by seed over every case: each tenth of a ten-seed suite is one seed of every case, so
  // the rate so far predicts the rest (the cases' diagnoses differ in cost several times over).
  for (int seed = 1; seed <= suite.seeds; ++seed) {
    for (CaseState& state : cases) {
      const size_t cell = state.cell_index;
      if (!state.result) {
        state.result = SetUpCase(suite, *state.cell, bases[cell], jobs[cell], *state.c, registry);
      }
      if (static_cast<int>(state.result->runs.size()) >= seed) continue;  // done before
      state.result->runs.push_back(
          RunSeed(*state.cell, bases[cell], jobs[cell], *state.result, seed, registry));
      progress.Advance();
      done[state.key] = ToJson(*state.result);
      AtomicWriteFile(CheckpointPath(suite), done.dump(1));
    }
  }
  std::vector<SuiteCaseResult> results;
  for (CaseState& state : cases) results.push_back(std::move(*state.result));
  return results;
}

namespace {

const std::string kBegin = "<!-- physics-suite:begin -->";
const std::string kEnd = "<!-- physics-suite:end -->";

// The document at `path` split around the markers: {before and with the begin marker, from the
// end marker on}; nullopt when there is no file. Throws InputError when there is one without
// both markers in order.
std::optional<std::pair<std::string, std::string>> AroundTheMarkers(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) return std::nullopt;
  const InputError refused({path, 0, 0},
                           "exists and has no " + kBegin + " ... " + kEnd +
                               " markers: the suite writes its tables between them and keeps "
                               "the rest, and would otherwise replace the whole document",
                           "Put the two markers on lines of their own where the tables go, or "
                           "name a file that does not exist yet (`output:` or -o)");
  if (!std::filesystem::is_regular_file(path, error)) throw refused;
  std::ifstream in(path);
  const std::string document((std::istreambuf_iterator<char>(in)), {});
  const size_t begin = document.find(kBegin), end = document.find(kEnd);
  if (begin == std::string::npos || end == std::string::npos || end < begin) throw refused;
  return std::make_pair(document.substr(0, begin + kBegin.size()), document.substr(end));
}

}  // namespace

void CheckPhysicsSuiteOutput(const std::string& path) { AroundTheMarkers(path); }

void WritePhysicsSuite(const PhysicsSuiteSpec& spec, const std::string& path,
                       const std::string& markdown) {
  const auto around = AroundTheMarkers(path);
  const std::string text = around ? around->first + "\n" + markdown + around->second
                                  : kBegin + "\n" + markdown + kEnd + "\n";
  AtomicWriteFile(path, text);
  std::filesystem::remove(CheckpointPath(spec));
}

}  // namespace cellmetry
