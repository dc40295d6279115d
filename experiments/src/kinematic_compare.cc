// The delta report's Table 7 on the one cell pipeline (kinematic_compare.h).
#include "cellmetry/experiments/kinematic_compare.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cellmetry/basics/error.h"
#include "cellmetry/basics/progress.h"
#include "cellmetry/cell/workcell.h"
#include "cellmetry/experiments/intervals.h"
#include "cellmetry/experiments/solver_compare.h"
#include "cellmetry/formats/checkpoint.h"

namespace cellmetry {
namespace {

// Table 7's figures: four decimals, an exponent below 1e-3.
constexpr FigureStyle kTable7 = FigureStyle::kFourDecimals;

// The report's words for the two residual forms.
std::string FormulationName(ResidualForm form) {
  return form == ResidualForm::kJointSpace ? "inverse" : "forward";
}

}  // namespace

CompareSpec LoadCompareSpec(const std::string& path, Registry& registry) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.ExpectKeys({"compare", "description", "simulation", "pose_sets", "sizes", "formulations",
                   "solvers", "validation_points", "seeds", "output"});
  if (root["compare"].AsString() != "kinematic") {
    throw root["compare"].Error("unknown comparison '" + root["compare"].AsString() + "'",
                                "Use compare: kinematic, markers, physics or solvers "
                                "(docs/formats.md)");
  }
  CompareSpec spec;
  spec.file = path;
  spec.simulation =
      LoadWorkcellSimulation(root.ResolvePath(root["simulation"].AsString()), registry);
  if (!spec.simulation.world_target.empty() || spec.simulation.robots.size() != 1 ||
      spec.simulation.robots[0].T_flange_target.size() != 1 ||
      spec.simulation.T_world_cam.size() != 1) {
    throw root["simulation"].Error(
        "Table 7 calibrates one arm with one marker seen by one "
        "camera, without a world target",
        "Point simulation: at such a spec (world_target: none)");
  }
  for (const auto& node : root["pose_sets"].Elements())
    spec.pose_sets.push_back(ParsePoseSet(node));
  for (const auto& node : root["sizes"].Elements()) {
    spec.sizes.push_back(node.AsInt());
    if (spec.sizes.back() < 1) throw node.Error("a pose set needs at least one sample");
  }
  for (const auto& node : root["formulations"].Elements()) {
    const std::string name = node.AsString();
    if (name != "forward" && name != "inverse") {
      throw node.Error("unknown formulation '" + name + "'", "Use forward or inverse");
    }
    spec.formulations.push_back(name == "forward" ? ResidualForm::kCartesian
                                                  : ResidualForm::kJointSpace);
  }
  const ConfigNode solvers = root["solvers"];
  for (const auto& label : solvers.Keys()) {
    const ConfigNode block = solvers[label];
    registry.CreateSolver(block["type"].AsString(), block);  // a bad option fails now
    spec.solvers.emplace_back(label, block);
  }
  // An empty list would make a table without rows, written at exit 0 as if it were an answer.
  const std::pair<const char*, bool> lists[] = {{"pose_sets", spec.pose_sets.empty()},
                                                {"sizes", spec.sizes.empty()},
                                                {"formulations", spec.formulations.empty()},
                                                {"solvers", spec.solvers.empty()}};
  for (const auto& [key, empty] : lists) {
    if (empty) {
      throw root[key].Error("lists nothing: the table would have no rows",
                            "Give at least one entry (docs/formats.md lists each key's choices)");
    }
  }
  spec.validation_points = root.GetIntIn("validation_points", spec.validation_points, 1, 1000000,
                                         "Fresh positions to score each row on; 1 or more");
  spec.seeds = root.GetIntIn("seeds", spec.seeds, 1, 100000,
                             "Repetitions of every row; 1 is the simulation's own draw alone");
  spec.output =
      root.Has("output") ? root.ResolvePath(root["output"].AsString()) : "results/compare";
  return spec;
}

namespace {

// What the table scores: the one marker in the one camera.
PredictedTarget Scored(const WorkcellSimulationSpec& sim) {
  const SimulatedRobot& robot = sim.robots.front();
  return {robot.name, robot.T_flange_target.begin()->first, sim.T_world_cam.begin()->first};
}

// The fresh positions: drawn from the truth's stream after the truth itself, as before the
// pipelines were one (the truth drawn again from `seed` is the simulation's own).
std::vector<std::vector<double>> ValidationCommands(const WorkcellSimulationSpec& sim, int count) {
  WorkcellSimulationSpec again = sim;
  std::mt19937 truth_rng(sim.seed);
  DrawTruth(&again, truth_rng);
  return DrawPoseSet(PoseSetGeometryOf(sim, sim.robots.front(), ""), PoseSet::kUniformWorkspace,
                     count, truth_rng);
}

CompareRow Score(const WorkcellSimulationSpec& sim, const WorkcellProblem& problem,
                 const Recording& recording, const WorkcellResult& result,
                 const std::vector<std::vector<double>>& validation) {
  CompareRow row;
  const WorkcellEstimate truth = TruthEstimate(sim);
  row.validation = ComparePredictions(*sim.robots.front().model, result.estimate, truth,
                                      Scored(sim), validation);
  if (!sim.sigma_position_mm.isZero()) {
    row.floor_rms_mm = PredictionErrorFloorMm(problem, recording, Scored(sim), validation, truth,
                                              result.unidentifiable);
  }
  row.iterations = result.solver.iterations;
  row.time_s = result.solver.time_s;
  row.stop_reason = result.solver.stop_reason;
  return row;
}

}  // namespace

namespace {

// One (pose set, size, seed)'s rows as kept in the checkpoint: the scores, not the labels,
// which the loops give again.
nlohmann::json RowsJson(const std::vector<CompareRow>& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const CompareRow& r : rows) {
    out.push_back({{"mean_mm", r.validation.mean_mm},
                   {"max_mm", r.validation.max_mm},
                   {"rms_mm", r.validation.rms_mm},
                   {"points", r.validation.points},
                   {"floor_rms_mm", r.floor_rms_mm},
                   {"iterations", r.iterations},
                   {"time_s", r.time_s},
                   {"stop_reason", r.stop_reason}});
  }
  return out;
}

void ReadScores(const nlohmann::json& j, CompareRow* r) {
  r->validation.mean_mm = j.at("mean_mm").get<double>();
  r->validation.max_mm = j.at("max_mm").get<double>();
  r->validation.rms_mm = j.at("rms_mm").get<double>();
  r->validation.points = j.at("points").get<int>();
  r->floor_rms_mm = j.at("floor_rms_mm").get<double>();
  r->iterations = j.at("iterations").get<int>();
  r->time_s = j.at("time_s").get<double>();
  r->stop_reason = j.at("stop_reason").get<std::string>();
}

// One recording per (pose set, size, seed), shared by every formulation and solver. Seed 0:
// the simulation's own truth (as with one seed); then a fresh truth per seed.
std::vector<CompareRow> RunOneDraw(const CompareSpec& spec, Registry& registry, PoseSet set,
                                   int size, int seed,
                                   const std::vector<std::vector<double>>& validation) {
  const WorkcellSimulationSpec& sim = spec.simulation;
  std::mt19937 rng(sim.seed * 7919u + static_cast<unsigned>(set) * 131u + size +
                   104729u * static_cast<unsigned>(seed));
  WorkcellSimulationSpec drawn = sim;
  drawn.robots.front().pose_set = PoseSetSpec{set, size, ""};
  Recording recording;
  if (seed == 0) {
    recording = SimulateWorkcell(drawn, nullptr, rng);
  } else {
    SimulatedDraw draw = DrawAndSimulate(drawn, rng);
    drawn = draw.truth;
    recording = std::move(draw.recording);
  }
  std::vector<CompareRow> rows;
  for (ResidualForm formulation : spec.formulations) {
    const WorkcellProblem problem = SimulatedProblem(sim, formulation);  // all free
    for (const auto& [label, block] : spec.solvers) {
      const SolverMaker make = [&, &block = block] {
        return registry.CreateSolver(block["type"].AsString(), block);
      };
      rows.push_back(
          Score(drawn, problem, recording, IdentifyWorkcell(problem, recording, make), validation));
    }
  }
  return rows;
}

}  // namespace

std::vector<CompareRow> RunComparison(const CompareSpec& spec, Registry& registry,
                                      const std::string& checkpoint) {
  const auto validation = ValidationCommands(spec.simulation, spec.validation_points);
  const int per_draw = static_cast<int>(spec.formulations.size() * spec.solvers.size());
  Checkpoint done(checkpoint, FileFingerprint(spec.file));
  std::vector<CompareRow> rows;
  // Counted in poses fitted, not rows: a draw's time grows about in proportion to its poses,
  // so a count of rows, the small sizes run first, would promise the end too soon.
  int total_poses = 0;
  for (int size : spec.sizes) total_poses += size;
  Progress progress("comparison poses fitted",
                    static_cast<int>(spec.pose_sets.size()) * total_poses * per_draw * spec.seeds);
  for (PoseSet set : spec.pose_sets) {
    for (int size : spec.sizes) {
      for (int seed = 0; seed < spec.seeds; ++seed) {
        const std::string key = std::to_string(static_cast<int>(set)) + "/" + std::to_string(size) +
                                "/" + std::to_string(seed);
        const nlohmann::json* piece = done.Find(key);
        std::vector<CompareRow> draw_rows(per_draw);
        if (piece != nullptr && piece->size() == draw_rows.size()) {
          for (size_t i = 0; i < draw_rows.size(); ++i) ReadScores((*piece)[i], &draw_rows[i]);
          progress.Resume(size * per_draw);
        } else {
          draw_rows = RunOneDraw(spec, registry, set, size, seed, validation);
          done.Put(key, RowsJson(draw_rows));
          progress.Advance(size * per_draw);
        }
        size_t i = 0;
        for (ResidualForm formulation : spec.formulations) {
          for (const auto& [label, block] : spec.solvers) {
            CompareRow& row = draw_rows[i++];
            row.pose_set = set;
            row.size = size;
            row.formulation = formulation;
            row.solver = label;
            row.seed = seed;
            rows.push_back(row);
          }
        }
      }
    }
  }
  return rows;
}

namespace {

// Rows over seeds: (pose set, size, formulation, solver) -> that row's seeds, in table order.
std::vector<std::vector<const CompareRow*>> BySeeds(const std::vector<CompareRow>& rows) {
  std::vector<std::vector<const CompareRow*>> groups;
  auto same = [](const CompareRow& a, const CompareRow& b) {
    return a.pose_set == b.pose_set && a.size == b.size && a.formulation == b.formulation &&
           a.solver == b.solver;
  };
  for (const auto& row : rows) {
    auto it = std::find_if(groups.begin(), groups.end(),
                           [&](const auto& g) { return same(*g.front(), row); });
    if (it == groups.end()) {
      groups.push_back({&row});
    } else {
      it->push_back(&row);
    }
  }
  return groups;
}

// The stop reasons' words (StopReasonWords), counted: "Function tolerance reached (9)".
std::string StopReasons(const std::vector<const CompareRow*>& group) {
  std::map<std::string, int> count;
  for (const CompareRow* r : group) ++count[StopReasonWords(r->stop_reason)];
  std::string text;
  for (const auto& [reason, n] : count) {
    text += (text.empty() ? "" : "; ") + reason + " (" + std::to_string(n) + ")";
  }
  return text;
}

std::string SeededMarkdown(const CompareSpec& spec, const std::vector<CompareRow>& rows) {
  std::ostringstream out;
  out << "| pose set | size | formulation | solver | RMS (mm) | mean (mm) | max (mm) | floor RMS "
         "(mm) | iterations (mean, min-max) | time (ms) | stop reasons |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& group : BySeeds(rows)) {
    std::vector<double> rms, mean, max, floor, time;
    int lo = group.front()->iterations, hi = lo;
    double iterations = 0.0;
    for (const CompareRow* r : group) {
      rms.push_back(r->validation.rms_mm);
      mean.push_back(r->validation.mean_mm);
      max.push_back(r->validation.max_mm);
      floor.push_back(r->floor_rms_mm);
      time.push_back(r->time_s);
      lo = std::min(lo, r->iterations);
      hi = std::max(hi, r->iterations);
      iterations += static_cast<double>(r->iterations) / group.size();
    }
    const CompareRow& r = *group.front();
    char iter[64];
    std::snprintf(iter, sizeof iter, "%.1f, %d-%d", iterations, lo, hi);
    out << "| " << PoseSetName(r.pose_set) << " | " << r.size << " | "
        << FormulationName(r.formulation) << " | " << r.solver << " | "
        << IntervalText(rms, 1.0, kTable7) << " | " << IntervalText(mean, 1.0, kTable7) << " | "
        << IntervalText(max, 1.0, kTable7) << " | "
        << (r.floor_rms_mm > 0 ? IntervalText(floor, 1.0, kTable7) : "-") << " | " << iter << " | "
        << IntervalText(time, 1e3, kTable7) << " | " << StopReasons(group) << " |\n";
  }
  out << "\nRecommendations (same: means within 1 %, or the 95 % t-interval of the per-seed "
         "differences contains 0; a tie is called a tie):\n\n";
  for (const auto& line : CompareRecommendations(spec, rows)) out << "- " << line << "\n";
  return out.str();
}

}  // namespace

std::vector<std::string> CompareRecommendations(const CompareSpec& spec,
                                                const std::vector<CompareRow>& rows) {
  std::vector<std::string> lines;
  for (PoseSet set : spec.pose_sets) {
    for (int size : spec.sizes) {
      std::vector<Contender> contenders;
      for (const auto& group : BySeeds(rows)) {
        const CompareRow& r = *group.front();
        if (r.pose_set != set || r.size != size) continue;
        Contender c;
        c.label = FormulationName(r.formulation) + " " + r.solver;
        for (const CompareRow* s : group) {
          c.error.push_back(s->validation.rms_mm);
          c.time_s.push_back(s->time_s);
        }
        contenders.push_back(c);
      }
      lines.push_back(Recommendation("for " + PoseSetName(set) + " x " + std::to_string(size) +
                                         ", which formulation and solver",
                                     contenders, "mm validation RMS"));
    }
  }
  return lines;
}

std::string CompareTableMarkdown(const CompareSpec& spec, const std::vector<CompareRow>& rows) {
  const Eigen::Vector3d& s = spec.simulation.sigma_position_mm;
  std::ostringstream out;
  out << "Validation error against the truth on " << spec.validation_points
      << " fresh positions (marker in the camera frame, mm); noise sigma (x, y, depth) = (" << s.x()
      << ", " << s.y() << ", " << s.z() << ") mm.\n\n";
  if (spec.seeds > 1) {
    out << spec.seeds << " seeds per row (seed 0 the simulation's own truth, each further one a "
        << "fresh truth and pose set): mean [95 % t-interval].\n\n"
        << SeededMarkdown(spec, rows);
    return out.str();
  }
  out << "| pose set | size | formulation | solver | mean (mm) | max (mm) | RMS (mm) | floor RMS "
         "(mm) "
         "| iterations | time (ms) |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    out << "| " << PoseSetName(r.pose_set) << " | " << r.size << " | "
        << FormulationName(r.formulation) << " | " << r.solver << " | "
        << FigureText(r.validation.mean_mm, kTable7) << " | "
        << FigureText(r.validation.max_mm, kTable7) << " | "
        << FigureText(r.validation.rms_mm, kTable7) << " | "
        << (r.floor_rms_mm > 0 ? FigureText(r.floor_rms_mm, kTable7) : "-") << " | " << r.iterations
        << " | " << FigureText(r.time_s * 1e3, kTable7) << " |\n";
  }
  return out.str();
}

std::string CompareTableCsv(const std::vector<CompareRow>& rows) {
  // A `seed` column with more than one seed; one seed writes the table as it always was.
  const bool seeded =
      std::any_of(rows.begin(), rows.end(), [](const CompareRow& r) { return r.seed > 0; });
  std::ostringstream out;
  out.precision(9);
  out << "pose_set,size,formulation,solver,mean_mm,max_mm,rms_mm,floor_rms_mm,iterations,time_s,"
         "stop_reason"
      << (seeded ? ",seed\n" : "\n");
  for (const auto& r : rows) {
    out << PoseSetName(r.pose_set) << "," << r.size << "," << FormulationName(r.formulation) << ","
        << r.solver << "," << r.validation.mean_mm << "," << r.validation.max_mm << ","
        << r.validation.rms_mm << "," << r.floor_rms_mm << "," << r.iterations << "," << r.time_s
        << ",\"" << r.stop_reason << "\"";
    if (seeded) out << "," << r.seed;
    out << "\n";
  }
  return out.str();
}

}  // namespace cellmetry
