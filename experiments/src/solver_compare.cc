// Solvers x camera models over seeds, with intervals and a recommendation (solver_compare.h).
#include "cellmetry/experiments/solver_compare.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/experiments/intervals.h"
#include "cellmetry/formats/checkpoint.h"
#include "cellmetry/formats/recording.h"

namespace cellmetry {

std::string StopReasonWords(const std::string& reason) {
  // The first clause: what stopped the solver. Its measured figures (a cost change of 2.2e-12)
  // differ per run and are left out; whole numbers (an epoch limit) are settings and stay.
  const std::string first = reason.substr(0, std::min(reason.find(". "), reason.find(';')));
  std::istringstream in(first);
  std::string words;
  for (std::string word; in >> word;) {
    const bool figure = std::isdigit(static_cast<unsigned char>(word[0])) &&
                        word.find_first_of(".eE") != std::string::npos;
    if (!figure) words += (words.empty() ? "" : " ") + word;
  }
  if (!words.empty() && words.back() == '.') words.pop_back();
  return words;
}

namespace {

// "1/4 the time" (the faster takes a quarter of the slower's time), "0.7x the time" when the
// two are within a factor 1.5.
std::string TimeRatio(double fast, double slow) {
  const double ratio = slow / fast;
  char text[48];
  if (ratio >= 1.5) {
    std::snprintf(text, sizeof text, "1/%.0f the time", std::round(ratio));
  } else {
    std::snprintf(text, sizeof text, "%.2gx the time", fast / slow);
  }
  return text;
}

// The contenders with their error's and time's 95 % intervals, and the phrases a
// recommendation is built from.
struct Scored {
  const std::vector<Contender>& contenders;
  const std::string& unit;
  double error_resolution;
  double time_resolution_s;
  std::vector<MeanInterval> error, time;

  std::string Label(size_t i) const { return contenders[i].label; }
  std::string Names(const std::vector<size_t>& list) const {
    std::string text;
    for (size_t i : list) text += (text.empty() ? "" : ", ") + Label(i);
    return text;
  }
  size_t FastestOf(const std::vector<size_t>& list) const {
    size_t f = list.front();
    for (size_t i : list) {
      if (time[i].mean < time[f].mean) f = i;
    }
    return f;
  }
  size_t MostAccurateOf(const std::vector<size_t>& list) const {
    size_t best = list.front();
    for (size_t i : list) {
      if (error[i].mean < error[best].mean) best = i;
    }
    return best;
  }
  bool SameError(size_t a, size_t b) const {
    return a == b || SameScore(contenders[a].error, contenders[b].error, error_resolution);
  }
  bool SameTime(size_t a, size_t b) const {
    return a == b || SameScore(contenders[a].time_s, contenders[b].time_s, time_resolution_s);
  }
};

// One contender more accurate than every other: it, the next most accurate, and its time where
// that is longer.
std::string MoreAccurate(const Scored& s, size_t best, size_t runner) {
  std::string line = s.Label(best) + ": more accurate than " + s.Label(runner) + " (" +
                     IntervalText(s.error[best]) + " vs " + IntervalText(s.error[runner]) + " " +
                     s.unit + ")";
  if (s.time[best].mean > s.time[runner].mean && !s.SameTime(best, runner)) {
    char text[64];
    std::snprintf(text, sizeof text, ", at %.2gx its time",
                  s.time[best].mean / s.time[runner].mean);
    line += text;
  }
  return line;
}

// Several as accurate as the best: the fastest of them, or a tie among the fastest.
std::string SameAccuracy(const Scored& s, const std::vector<size_t>& same) {
  const size_t fastest = s.FastestOf(same);
  std::vector<size_t> quick, slow;  // as fast as the fastest (it included), slower
  for (size_t i : same) (s.SameTime(i, fastest) ? quick : slow).push_back(i);
  if (quick.size() == 1) {
    const size_t next = s.FastestOf(slow);
    return s.Label(fastest) + ": same accuracy as " + s.Label(next) + " at " +
           TimeRatio(s.time[fastest].mean, s.time[next].mean) + " (" +
           IntervalText(s.error[fastest]) + " vs " + IntervalText(s.error[next]) + " " + s.unit +
           "; " + IntervalText(s.time[fastest], 1e3) + " vs " + IntervalText(s.time[next], 1e3) +
           " ms)";
  }
  std::string line = "tie: " + s.Names(quick) + " (same accuracy, " +
                     IntervalText(s.error[fastest]) + " " + s.unit + ", and same time)";
  if (!slow.empty()) {
    const size_t next = s.FastestOf(slow);
    char text[96];
    std::snprintf(text, sizeof text, ": same accuracy at %.2gx the time",
                  s.time[next].mean / s.time[fastest].mean);
    line += "; " + s.Names(slow) + text + (slow.size() > 1 ? " or more" : "");
  }
  return line;
}

}  // namespace

std::string Recommendation(const std::string& question, const std::vector<Contender>& contenders,
                           const std::string& unit, double error_resolution,
                           double time_resolution_s) {
  if (contenders.empty()) return question + ": nothing to compare";
  if (contenders.size() == 1) return question + ": " + contenders[0].label + " (the only one)";
  Scored s{contenders, unit, error_resolution, time_resolution_s, {}, {}};
  std::vector<size_t> all;
  for (size_t i = 0; i < contenders.size(); ++i) {
    s.error.push_back(TInterval95(contenders[i].error));
    s.time.push_back(TInterval95(contenders[i].time_s));
    all.push_back(i);
  }
  const size_t best = s.MostAccurateOf(all);
  std::vector<size_t> same, worse;  // same accuracy as the best (best included), less accurate
  for (size_t i : all) (s.SameError(i, best) ? same : worse).push_back(i);
  std::string line = question + ": ";
  size_t runner = contenders.size();  // the less accurate one named in the line, if any
  if (same.size() == 1) {
    runner = s.MostAccurateOf(worse);
    line += MoreAccurate(s, best, runner);
  } else {
    line += SameAccuracy(s, same);
  }
  std::vector<size_t> others;  // less accurate, not yet named
  for (size_t i : worse) {
    if (i != runner) others.push_back(i);
  }
  if (!others.empty()) line += "; less accurate: " + s.Names(others);
  return line;
}

namespace {

CameraModel ParseCameraModel(const ConfigNode& node) {
  const std::string name = node.AsString();
  if (name == "static_cameras") return CameraModel::kStaticCameras;
  if (name == "per_frame") return CameraModel::kPerFrame;
  throw node.Error("unknown camera model '" + name + "'", "Use static_cameras or per_frame");
}

bool HasTruth(const SolverCompareSpec& spec) { return spec.simulation.has_value(); }

std::string Unit(const SolverCompareSpec&) { return "mm"; }

std::string MetricText(const SolverCompareSpec& spec) {
  return HasTruth(spec) ? "error of the robots' base positions against the truth (RMS over robots, "
                          "mm); a fresh noise draw per seed"
                        : "held-out RMS of the carried targets (k-fold by pose, mm); no truth: the "
                          "seed varies the fold assignment";
}

}  // namespace

SolverCompareSpec LoadSolverCompare(const std::string& path, Registry& registry) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"compare", "description", "job", "simulation", "solvers", "camera_models",
                   "seeds", "output"});
  SolverCompareSpec spec;
  spec.file = path;
  spec.description = root.GetString("description", "");
  const bool simulated = root.Has("simulation");
  spec.job = LoadWorkcellJob(root.ResolvePath(root["job"].AsString()), registry, !simulated);
  spec.job.problem.uncertain_inputs = {};
  if (simulated) {
    spec.simulation =
        LoadWorkcellSimulation(root.ResolvePath(root["simulation"].AsString()), registry);
  }
  const ConfigNode solvers = root["solvers"];
  for (const auto& label : solvers.Keys()) {
    const ConfigNode block = solvers[label];
    registry.CreateSolver(block["type"].AsString(), block);  // a bad option fails now
    spec.solvers.emplace_back(label, block);
  }
  // An empty list would make a table without rows, written at exit 0 as if it were an answer.
  if (spec.solvers.empty()) {
    throw solvers.Error("lists no solver: the table would have no rows",
                        "Give at least one, e.g. lm: {type: ceres_lm}");
  }
  if (root.Has("camera_models")) {
    for (const auto& node : root["camera_models"].Elements()) {
      spec.camera_models.push_back(ParseCameraModel(node));
    }
    if (spec.camera_models.empty()) {
      throw root["camera_models"].Error("lists no camera model: the table would have no rows",
                                        "Give static_cameras, per_frame or both, or leave the "
                                        "key out for both");
    }
  } else {
    spec.camera_models = {CameraModel::kStaticCameras, CameraModel::kPerFrame};
  }
  spec.seeds = root.GetIntIn("seeds", spec.seeds, 1, 100000,
                             "Repetitions per row; 10 or more gives a useful interval");
  spec.output =
      root.Has("output") ? root.ResolvePath(root["output"].AsString()) : "results/compare_solvers";
  return spec;
}

namespace {

// The score of one fit: the bases' position error against the truth (RMS over robots), or the
// held-out RMS without a truth.
double ScoreOf(const SolverCompareSpec& spec, const WorkcellResult& result) {
  if (!HasTruth(spec)) return result.held_out.total.norm;
  double error = 0.0;
  for (const auto& robot : spec.simulation->robots) {
    const Pose& found = result.estimate.T_world_base.at(robot.name);
    error += (found.t - robot.T_world_base.t).squaredNorm();
  }
  return std::sqrt(error / spec.simulation->robots.size());
}

// Appends one seed's fits (one entry per row, in row order) to `rows`.
void ReadSeed(const nlohmann::json& seed, std::vector<SolverCompareRow>* rows) {
  for (size_t r = 0; r < rows->size() && r < seed.size(); ++r) {
    SolverCompareRow& row = (*rows)[r];
    row.error_mm.push_back(seed[r]["error_mm"].get<double>());
    row.time_s.push_back(seed[r]["time_s"].get<double>());
    row.iterations.push_back(seed[r]["iterations"].get<int>());
    row.converged += seed[r]["converged"].get<bool>() ? 1 : 0;
    ++row.stop_reasons[seed[r]["stop_reason"].get<std::string>()];
  }
}

}  // namespace

std::vector<SolverCompareRow> RunSolverCompare(const SolverCompareSpec& spec, Registry& registry,
                                               const std::string& checkpoint) {
  std::vector<SolverCompareRow> rows;
  for (CameraModel model : spec.camera_models) {
    for (const auto& [label, block] : spec.solvers) {
      SolverCompareRow row;
      row.camera_model = model;
      row.solver = label;
      rows.push_back(row);
    }
  }
  std::optional<Recording> recorded;
  if (!HasTruth(spec)) {
    recorded = ReadRecording(spec.job.recording);
    ValidateJobAgainstRecording(spec.job, *recorded);
  }
  Checkpoint done(checkpoint, FileFingerprint(spec.file));
  Progress progress("comparison seed", spec.seeds);
  for (int seed = 0; seed < spec.seeds; ++seed) {
    if (const nlohmann::json* piece = done.Find(std::to_string(seed))) {
      ReadSeed(*piece, &rows);
      progress.Resume(1);
      continue;
    }
    std::optional<Recording> simulated;
    WorkcellProblem problem = spec.job.problem;
    problem.leave_one_camera_out = false;  // solvers are compared, not cameras
    if (HasTruth(spec)) {
      WorkcellSimulationSpec sim = *spec.simulation;
      sim.noise_seed = spec.simulation->noise_seed + 1000u * static_cast<unsigned>(seed + 1);
      simulated = SimulateWorkcell(sim, nullptr);
      if (seed == 0) ValidateJobAgainstRecording(spec.job, *simulated);
      problem.folds = 0;  // scored against the truth
    } else {
      if (problem.folds < 2) problem.folds = 5;
      problem.seed = static_cast<unsigned>(seed + 1);
    }
    const Recording& recording = simulated ? *simulated : *recorded;
    nlohmann::json seed_json = nlohmann::json::array();
    for (CameraModel model : spec.camera_models) {
      problem.camera_model = model;
      for (const auto& [label, block] : spec.solvers) {
        const SolverMaker make = [&registry, &block = block] {
          return registry.CreateSolver(block["type"].AsString(), block);
        };
        const WorkcellResult result = IdentifyWorkcell(problem, recording, make);
        seed_json.push_back({{"error_mm", ScoreOf(spec, result)},
                             {"time_s", result.solver.time_s},
                             {"iterations", result.solver.iterations},
                             {"converged", result.solver.converged},
                             {"stop_reason", StopReasonWords(result.solver.stop_reason)}});
      }
    }
    done.Put(std::to_string(seed), seed_json);
    ReadSeed(seed_json, &rows);
    progress.Advance();
  }
  return rows;
}

std::vector<std::string> SolverCompareRecommendations(const SolverCompareSpec& spec,
                                                      const std::vector<SolverCompareRow>& rows) {
  std::vector<std::string> lines;
  const std::string what = HasTruth(spec) ? "base error" : "held-out RMS";
  for (CameraModel model : spec.camera_models) {
    std::vector<Contender> contenders;
    for (const auto& row : rows) {
      if (row.camera_model == model) contenders.push_back({row.solver, row.error_mm, row.time_s});
    }
    if (contenders.size() > 1) {
      lines.push_back(Recommendation("for this cell, " + CameraModelName(model) + ", which solver",
                                     contenders, "mm " + what));
    }
  }
  if (spec.camera_models.size() > 1) {
    for (const auto& [label, block] : spec.solvers) {
      std::vector<Contender> contenders;
      for (const auto& row : rows) {
        if (row.solver == label) {
          contenders.push_back({CameraModelName(row.camera_model), row.error_mm, row.time_s});
        }
      }
      lines.push_back(Recommendation("for this cell, " + label + ", which camera model", contenders,
                                     "mm " + what));
    }
  }
  return lines;
}

std::string SolverCompareMarkdown(const SolverCompareSpec& spec,
                                  const std::vector<SolverCompareRow>& rows) {
  std::ostringstream out;
  if (!spec.description.empty()) out << spec.description << "\n\n";
  out << "Score: " << MetricText(spec) << ". " << spec.seeds
      << " seeds per row; mean [95 % t-interval].\n\n";
  out << "| camera model | solver | " << (HasTruth(spec) ? "base error" : "held-out RMS") << " ("
      << Unit(spec)
      << ") | solver time (ms) | iterations (mean, min-max) | converged | "
         "stop reasons |\n";
  out << "|---|---|---|---|---|---|---|\n";
  for (const auto& row : rows) {
    const auto [lo, hi] = std::minmax_element(row.iterations.begin(), row.iterations.end());
    double mean_iterations = 0.0;
    for (int i : row.iterations) mean_iterations += static_cast<double>(i) / row.iterations.size();
    std::string reasons;
    for (const auto& [reason, count] : row.stop_reasons) {
      reasons += (reasons.empty() ? "" : "; ") + reason + " (" + std::to_string(count) + ")";
    }
    char iterations[64];
    std::snprintf(iterations, sizeof iterations, "%.1f, %d-%d", mean_iterations,
                  row.iterations.empty() ? 0 : *lo, row.iterations.empty() ? 0 : *hi);
    out << "| " << CameraModelName(row.camera_model) << " | " << row.solver << " | "
        << IntervalText(TInterval95(row.error_mm)) << " | "
        << IntervalText(TInterval95(row.time_s), 1e3) << " | " << iterations << " | "
        << row.converged << "/" << row.error_mm.size() << " | " << reasons << " |\n";
  }
  out << "\nRecommendations (the same accuracy or time: means within 1 %, or the 95 % "
         "t-interval of the per-seed differences contains 0, every row having run on the same "
         "data for a seed; a tie is called a tie):\n\n";
  for (const auto& line : SolverCompareRecommendations(spec, rows)) out << "- " << line << "\n";
  return out.str();
}

std::string SolverCompareCsv(const std::vector<SolverCompareRow>& rows) {
  std::ostringstream out;
  out.precision(9);
  out << "camera_model,solver,seed,error_mm,time_s,iterations\n";
  for (const auto& row : rows) {
    for (size_t i = 0; i < row.error_mm.size(); ++i) {
      out << CameraModelName(row.camera_model) << "," << row.solver << "," << i << ","
          << row.error_mm[i] << "," << row.time_s[i] << "," << row.iterations[i] << "\n";
    }
  }
  return out.str();
}

}  // namespace cellmetry
