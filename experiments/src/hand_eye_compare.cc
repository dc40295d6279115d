// cellmetry against OpenCV's hand-eye methods, over seeds (hand_eye_compare.h).
#include "cellmetry/experiments/hand_eye_compare.h"

#include <chrono>
#include <cmath>
#include <sstream>

#include <opencv2/core.hpp>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/experiments/intervals.h"
#include "cellmetry/experiments/solver_compare.h"
#include "cellmetry/formats/checkpoint.h"
#include "opencv_hand_eye.h"

namespace cellmetry {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The one robot, camera and board of a hand-eye cell into `spec`, or an InputError at `where`
// saying what is missing. Eye-in-hand: the one camera rides on the robot and sees the world
// target; eye-to-hand: the one camera stands still and sees the one board the robot carries,
// with no world target.
void ReadCell(const ConfigNode& where, HandEyeCompareSpec* spec) {
  const WorkcellSimulationSpec& sim = spec->simulation;
  const size_t riding = sim.robots.empty() ? 0 : sim.robots.front().T_flange_camera.size();
  if (sim.robots.size() != 1 || sim.T_world_cam.size() + riding != 1) {
    throw where.Error("is not a hand-eye cell: it has " + std::to_string(sim.robots.size()) +
                          " robots and " + std::to_string(sim.T_world_cam.size() + riding) +
                          " cameras",
                      "Simulate one robot and one camera");
  }
  const SimulatedRobot& robot = sim.robots.front();
  spec->robot = robot.name;
  if (riding == 1) {
    if (sim.world_target.empty()) {
      throw where.Error(
          "is not an eye-in-hand cell: the camera on the flange needs a static "
          "board, the world target",
          "See configs/simulations/ur3_eye_in_hand.yaml");
    }
    spec->setup = HandEyeSetup::kEyeInHand;
    spec->camera = robot.T_flange_camera.begin()->first;
    spec->board = sim.world_target;
    return;
  }
  if (!sim.world_target.empty() || robot.T_flange_target.size() != 1 ||
      !robot.point_targets.empty()) {
    throw where.Error(
        "is not an eye-to-hand cell: it needs world_target: none and one board "
        "(not a point) on the robot's tool",
        "See configs/simulations/ur3_eye_to_hand.yaml");
  }
  spec->setup = HandEyeSetup::kEyeToHand;
  spec->camera = sim.T_world_cam.begin()->first;
  spec->board = robot.T_flange_target.begin()->first;
}

// The hand-eye frame: T_flange_cam (eye-in-hand) or T_base_cam (eye-to-hand), its truth and
// cellmetry's answer.
Pose TruthOf(const HandEyeCompareSpec& spec) {
  const SimulatedRobot& robot = spec.simulation.robots.front();
  if (spec.setup == HandEyeSetup::kEyeInHand) return robot.T_flange_camera.at(spec.camera);
  return robot.T_world_base.inverse() * spec.simulation.T_world_cam.at(spec.camera);
}

Pose AnswerOf(const WorkcellEstimate& estimate, const HandEyeCompareSpec& spec) {
  if (spec.setup == HandEyeSetup::kEyeInHand) {
    return estimate.T_flange_target.at(spec.robot + "." + spec.camera);
  }
  return estimate.T_world_base.at(spec.robot).inverse() * estimate.T_world_cam.at(spec.camera);
}

// The captures every OpenCV method reads: each observation of the board with its rotation, and
// the nominal model's flange pose at the sample's joints.
HandEyeCaptures CapturesOf(const Recording& recording, const WorkcellRobot& robot,
                           const HandEyeCompareSpec& spec) {
  std::vector<double> nominal;
  for (const Parameter& p : robot.model_parameters) nominal.push_back(p.nominal);
  HandEyeCaptures captures;
  captures.eye_in_hand = spec.setup == HandEyeSetup::kEyeInHand;
  for (const Observation& obs : recording.observations) {
    if (obs.camera != spec.camera || obs.target != spec.board || !obs.rvec) continue;
    const Sample& sample = recording.samples[recording.SampleIndex(obs.sample)];
    Pose T_base_flange;
    if (!robot.model->Forward(sample.q.data(), nominal.data(), &T_base_flange)) continue;
    captures.T_base_flange.push_back(T_base_flange);
    captures.T_cam_board.push_back(PoseFromRvecT(*obs.rvec, obs.position_mm));
  }
  return captures;
}

void Score(const Pose& found, const Pose& truth, double time_s, HandEyeCompareRow* row) {
  const double position = (found.t - truth.t).norm();
  const double rotation = RvecFromRotation(found.R * truth.R.transpose()).norm() * 1e3;
  if (!std::isfinite(position) || !std::isfinite(rotation)) {
    ++row->failed;
    return;
  }
  row->position_error_mm.push_back(position);
  row->rotation_error_mrad.push_back(rotation);
  row->time_s.push_back(time_s);
}

// One seed's scores, one entry per method in row order ({} where it gave no answer).
nlohmann::json SeedJson(const std::vector<HandEyeCompareRow>& seed_rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& row : seed_rows) {
    if (row.position_error_mm.empty()) {
      out.push_back(nlohmann::json::object());
      continue;
    }
    out.push_back({{"position_error_mm", row.position_error_mm[0]},
                   {"rotation_error_mrad", row.rotation_error_mrad[0]},
                   {"time_s", row.time_s[0]}});
  }
  return out;
}

// Appends one seed's scores (SeedJson) to `rows`.
void ReadSeed(const nlohmann::json& seed, std::vector<HandEyeCompareRow>* rows) {
  for (size_t m = 0; m < rows->size() && m < seed.size(); ++m) {
    HandEyeCompareRow& row = (*rows)[m];
    if (!seed[m].contains("position_error_mm")) {
      ++row.failed;
      continue;
    }
    row.position_error_mm.push_back(seed[m]["position_error_mm"].get<double>());
    row.rotation_error_mrad.push_back(seed[m]["rotation_error_mrad"].get<double>());
    row.time_s.push_back(seed[m]["time_s"].get<double>());
  }
}

}  // namespace

std::string HandEyeSetupName(HandEyeSetup setup) {
  return setup == HandEyeSetup::kEyeInHand ? "eye-in-hand" : "eye-to-hand";
}

HandEyeCompareSpec LoadHandEyeCompare(const std::string& path, Registry& registry) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"compare", "description", "simulation", "job", "seeds", "output"});
  HandEyeCompareSpec spec;
  spec.file = path;
  spec.description = root.GetString("description", "");
  spec.simulation =
      LoadWorkcellSimulation(root.ResolvePath(root["simulation"].AsString()), registry);
  ReadCell(root["simulation"], &spec);
  spec.job = LoadWorkcellJob(root.ResolvePath(root["job"].AsString()), registry,
                             /*recording_must_exist=*/false);
  spec.job.problem.uncertain_inputs = {};
  spec.job.problem.folds = 0;  // scored against the truth
  spec.job.problem.leave_one_camera_out = false;
  spec.seeds = root.GetIntIn("seeds", spec.seeds, 2, 100000,
                             "Repetitions per method; 10 or more gives a useful interval");
  spec.output =
      root.Has("output") ? root.ResolvePath(root["output"].AsString()) : "results/compare_hand_eye";
  return spec;
}

std::vector<HandEyeCompareRow> RunHandEyeCompare(const HandEyeCompareSpec& spec,
                                                 const std::string& checkpoint) {
  std::vector<HandEyeCompareRow> rows(1 + OpenCvHandEyeMethods().size());
  rows[0].method = "cellmetry";
  for (size_t m = 0; m < OpenCvHandEyeMethods().size(); ++m) {
    rows[m + 1].method = OpenCvHandEyeMethods()[m];
  }
  const Pose truth = TruthOf(spec);
  Registry& registry = Registry::Global();
  const SolverMaker make_solver = [&] {
    return registry.CreateSolver(spec.job.solver_type, *spec.job.solver_config);
  };
  Checkpoint done(checkpoint, FileFingerprint(spec.file));
  Progress progress("hand-eye seed", spec.seeds);
  for (int seed = 0; seed < spec.seeds; ++seed) {
    if (const nlohmann::json* piece = done.Find(std::to_string(seed))) {
      ReadSeed(*piece, &rows);
      progress.Resume(1);
      continue;
    }
    WorkcellSimulationSpec sim = spec.simulation;
    sim.noise_seed = spec.simulation.noise_seed + 1000u * static_cast<unsigned>(seed + 1);
    const Recording recording = SimulateWorkcell(sim, nullptr);
    if (seed == 0) ValidateJobAgainstRecording(spec.job, recording);
    std::vector<HandEyeCompareRow> seed_rows(rows.size());
    Clock::time_point start = Clock::now();
    const WorkcellResult result = IdentifyWorkcell(spec.job.problem, recording, make_solver);
    Score(AnswerOf(result.estimate, spec), truth, SecondsSince(start), &seed_rows[0]);
    const HandEyeCaptures captures = CapturesOf(recording, spec.job.problem.robots.front(), spec);
    for (size_t m = 0; m < OpenCvHandEyeMethods().size(); ++m) {
      start = Clock::now();
      Pose found;
      try {
        found = OpenCvHandEye(OpenCvHandEyeMethods()[m], captures);
      } catch (const cv::Exception&) {
        ++seed_rows[m + 1].failed;
        continue;
      }
      Score(found, truth, SecondsSince(start), &seed_rows[m + 1]);
    }
    done.Put(std::to_string(seed), SeedJson(seed_rows));
    ReadSeed(SeedJson(seed_rows), &rows);
    progress.Advance();
  }
  return rows;
}

std::vector<std::string> HandEyeRecommendations(const std::vector<HandEyeCompareRow>& rows) {
  std::vector<Contender> by_position, by_rotation;
  for (const auto& row : rows) {
    if (row.failed > 0) continue;  // a method that sometimes gives no answer is not recommended
    by_position.push_back({row.method, row.position_error_mm, row.time_s});
    by_rotation.push_back({row.method, row.rotation_error_mrad, row.time_s});
  }
  return {Recommendation("which method, by the hand-eye frame's position", by_position, "mm", 1e-6,
                         1e-5),
          Recommendation("which method, by its rotation", by_rotation, "mrad", 1e-6, 1e-5)};
}

std::string HandEyeCompareMarkdown(const HandEyeCompareSpec& spec,
                                   const std::vector<HandEyeCompareRow>& rows) {
  std::ostringstream out;
  if (!spec.description.empty()) out << spec.description << "\n\n";
  out << "Setup: " << HandEyeSetupName(spec.setup)
      << ". Score: the hand-eye frame's error against the simulation's truth (position: "
         "distance, mm; rotation: angle, mrad); a fresh noise draw per seed, every method on "
         "the same captures. "
      << spec.seeds << " seeds; mean [95 % t-interval].\n\n";
  out << "| method | position error (mm) | rotation error (mrad) | time (ms) | failed | known "
         "fault |\n";
  out << "|---|---|---|---|---|---|\n";
  for (const auto& row : rows) {
    out << "| " << row.method << " | " << IntervalText(row.position_error_mm) << " | "
        << IntervalText(row.rotation_error_mrad) << " | " << IntervalText(row.time_s, 1e3) << " | "
        << row.failed << "/" << spec.seeds << " | "
        << (row.method == "cellmetry" ? "" : OpenCvHandEyeFault(row.method)) << " |\n";
  }
  out << "\nRecommendations (the same accuracy or time: means within 1 %, or the 95 % "
         "t-interval of the per-seed differences contains 0; a tie is called a tie):\n\n";
  for (const auto& line : HandEyeRecommendations(rows)) out << "- " << line << "\n";
  return out.str();
}

std::string HandEyeCompareCsv(const std::vector<HandEyeCompareRow>& rows) {
  std::ostringstream out;
  out.precision(9);
  out << "method,seed,position_error_mm,rotation_error_mrad,time_s\n";
  for (const auto& row : rows) {
    for (size_t i = 0; i < row.position_error_mm.size(); ++i) {
      out << row.method << "," << i << "," << row.position_error_mm[i] << ","
          << row.rotation_error_mrad[i] << "," << row.time_s[i] << "\n";
    }
  }
  return out.str();
}

}  // namespace cellmetry
