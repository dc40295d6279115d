// `cellmetry compare SPEC.yaml`: the report's Table 7 (`compare: kinematic`, kinematic_compare.h)
// or its Tables 3 and 4 (`compare: markers`, marker_comparison.h), writing table.md and
// table.csv; or the physics finder's concealed-effect suite (`compare: physics`,
// physics_suite.h: rates with Wilson intervals and a decision per question), writing one
// markdown file; or solvers x camera models over seeds with a
// recommendation per question (`compare: solvers`, solver_compare.h); or cellmetry's hand-eye
// fit against OpenCV's hand-eye methods (`compare: hand_eye`, hand_eye_compare.h).
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <utility>

#include "cellmetry/basics/progress.h"
#include "cellmetry/diagnosis/diagnosis_job.h"
#include "cellmetry/experiments/concealed_physics.h"
#include "cellmetry/experiments/hand_eye_compare.h"
#include "cellmetry/experiments/kinematic_compare.h"
#include "cellmetry/experiments/marker_comparison.h"
#include "cellmetry/experiments/physics_suite.h"
#include "cellmetry/experiments/solver_compare.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/report/reports.h"
#include "commands.h"

namespace cellmetry::app {
namespace {

// A table-writing comparison, loaded: where it writes by default, and the work that makes its
// table.md and table.csv (run only after the output folder was found replaceable). `run` takes
// the path of its checkpoint of finished work (beside the output folder), which the caller
// removes once the tables are written; a kind without one ignores it.
struct TableComparison {
  std::string output;
  std::function<std::pair<std::string, std::string>(const std::string& checkpoint)> run;
};

TableComparison LoadMarkers(const std::string& path, int seeds) {
  auto spec =
      std::make_shared<MarkerComparisonSpec>(LoadMarkerComparison(path, Registry::Global()));
  if (seeds > 0) spec->seeds = seeds;
  return {spec->output, [spec](const std::string& checkpoint) {
            if (spec->seeds > 1) {  // every figure over seeds, with a recommendation
              const auto per_seed = CompareMarkersOverSeeds(*spec, Registry::Global(), checkpoint);
              return std::pair(MarkerSeedsMarkdown(*spec, per_seed),
                               MarkerSeedsCsv(*spec, per_seed));
            }
            const auto rows = CompareMarkers(*spec, Registry::Global());
            return std::pair(MarkerTableMarkdown(*spec, rows), MarkerTableCsv(rows));
          }};
}

TableComparison LoadSolvers(const std::string& path, int seeds) {
  auto spec = std::make_shared<SolverCompareSpec>(LoadSolverCompare(path, Registry::Global()));
  if (seeds > 0) spec->seeds = seeds;
  return {spec->output, [spec](const std::string& checkpoint) {
            const auto rows = RunSolverCompare(*spec, Registry::Global(), checkpoint);
            return std::pair(SolverCompareMarkdown(*spec, rows), SolverCompareCsv(rows));
          }};
}

TableComparison LoadHandEye(const std::string& path, int seeds) {
  auto spec = std::make_shared<HandEyeCompareSpec>(LoadHandEyeCompare(path, Registry::Global()));
  if (seeds > 0) spec->seeds = seeds;
  return {spec->output, [spec](const std::string& checkpoint) {
            const auto rows = RunHandEyeCompare(*spec, checkpoint);
            return std::pair(HandEyeCompareMarkdown(*spec, rows), HandEyeCompareCsv(rows));
          }};
}

TableComparison LoadKinematic(const std::string& path, int seeds) {
  auto spec = std::make_shared<CompareSpec>(LoadCompareSpec(path, Registry::Global()));
  if (seeds > 0) spec->seeds = seeds;
  return {spec->output, [spec](const std::string& checkpoint) {
            const auto rows = RunComparison(*spec, Registry::Global(), checkpoint);
            return std::pair(CompareTableMarkdown(*spec, rows), CompareTableCsv(rows));
          }};
}

}  // namespace

void AddCompareCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand(
      "compare", "calibrate simulated arms per pose set x size x formulation x solver (Table 7)");
  static std::string spec_path, output;
  cmd->add_option(
         "spec", spec_path,
         "comparison spec (YAML, compare: kinematic | markers | physics | solvers | hand_eye)")
      ->required();
  cmd->add_option("-o,--output", output, "folder for table.md and table.csv");
  static int seeds = 0;
  cmd->add_option("--seeds", seeds,
                  "repetitions per row instead of the spec's seeds (every kind; "
                  "kinematic and markers: 1 gives the one-seed table)")
      ->check(CLI::Range(1, 100000));
  cmd->callback([&context] {
    Progress::SetQuiet(context.quiet);
    LoadPlugins(context);
    const ConfigNode root = ConfigNode::LoadFile(spec_path);
    const std::string kind = root["compare"].AsString();
    if (kind != "physics" && kind != "markers" && kind != "kinematic" && kind != "solvers" &&
        kind != "hand_eye") {
      throw root["compare"].Error(
          "unknown comparison '" + kind + "'",
          "Use compare: kinematic (Table 7: pose sets x sizes x formulations x solvers), markers "
          "(Tables 3 and 4: marker detectors), physics (the concealed-effect suite), solvers "
          "(solvers x camera models over seeds, with a recommendation) or hand_eye (cellmetry "
          "against OpenCV's hand-eye methods); docs/formats.md");
    }
    if (kind == "physics") {
      PhysicsSuiteSpec spec = LoadPhysicsSuite(spec_path);
      if (seeds > 0) spec.seeds = seeds;
      for (const auto& cell : spec.cells) {  // what the runs would read, read now
        LoadWorkcellSimulation(cell.simulation, Registry::Global(), ReadConcealedDisturbance);
        LoadDiagnosisJob(cell.job, Registry::Global(), /*recording_must_exist=*/false);
      }
      CheckPhysicsSuiteOutput(output.empty() ? spec.output : output);  // before the work
      if (StopAfterCheck(output.empty() ? spec.output : output)) return;
      const auto results = RunPhysicsSuite(spec, Registry::Global());
      const std::string table = PhysicsSuiteMarkdown(spec, results);
      WritePhysicsSuite(spec, output.empty() ? spec.output : output, table);
      std::printf("%s  written: %s\n", table.c_str(),
                  (output.empty() ? spec.output : output).c_str());
      return;
    }
    const TableComparison comparison = kind == "markers"    ? LoadMarkers(spec_path, seeds)
                                       : kind == "solvers"  ? LoadSolvers(spec_path, seeds)
                                       : kind == "hand_eye" ? LoadHandEye(spec_path, seeds)
                                                            : LoadKinematic(spec_path, seeds);
    const std::string folder = output.empty() ? comparison.output : output;
    CheckReplaceable(folder, "comparison");  // before the work, not after it
    if (StopAfterCheck(folder)) return;
    const std::string checkpoint = folder + ".partial.json";
    const auto [table, csv] = comparison.run(checkpoint);
    StagedDirectory out(folder, "comparison");
    AtomicWriteFile(out.File("table.md"), table);
    AtomicWriteFile(out.File("table.csv"), csv);
    AtomicWriteFile(out.File(report::kReportFile),
                    report::CompareReportHtml(csv, table, "cellmetry compare: " + spec_path));
    out.Commit();
    std::filesystem::remove(checkpoint);
    std::printf("%s  written: %s/{table.md,table.csv,report.html}\n", table.c_str(),
                folder.c_str());
  });
}

}  // namespace cellmetry::app
