// `cellmetry compare SPEC.yaml`: the report's Table 7 (`compare: kinematic`, kinematic_compare.h)
// or its Tables 3 and 4 (`compare: markers`, marker_comparison.h), writing table.md and
// table.csv; or the physics finder's concealed-effect suite (`compare: physics`,
// physics_suite.h: rates with Wilson intervals and a decision per question), writing one
// markdown file; or solvers x camera models over seeds with a
// recommendation per question (`compare: solvers`, solver_compare.h).
#include <cstdio>

#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/report/reports.h"
#include "cellmetry/experiments/kinematic_compare.h"
#include "cellmetry/experiments/marker_comparison.h"
#include "cellmetry/experiments/physics_suite.h"
#include "cellmetry/experiments/solver_compare.h"
#include "cellmetry/basics/progress.h"
#include "commands.h"

namespace cellmetry::app {

void AddCompareCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand(
      "compare", "calibrate simulated arms per pose set x size x formulation x solver (Table 7)");
  static std::string spec_path, output;
  cmd->add_option("spec", spec_path,
                  "comparison spec (YAML, compare: kinematic | markers | physics | solvers)")
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
    if (kind != "physics" && kind != "markers" && kind != "kinematic" && kind != "solvers") {
      throw root["compare"].Error(
          "unknown comparison '" + kind + "'",
          "Use compare: kinematic (Table 7: pose sets x sizes x formulations x solvers), markers "
          "(Tables 3 and 4: marker detectors), physics (the concealed-effect suite) or solvers "
          "(solvers x camera models over seeds, with a recommendation); docs/formats.md");
    }
    std::string table, csv, folder;
    if (kind == "physics") {
      PhysicsSuiteSpec spec = LoadPhysicsSuite(spec_path);
      if (seeds > 0) spec.seeds = seeds;
      const auto results = RunPhysicsSuite(spec, Registry::Global());
      table = PhysicsSuiteMarkdown(spec, results);
      WritePhysicsSuite(spec, output.empty() ? spec.output : output, table);
      std::printf("%s  written: %s\n", table.c_str(), (output.empty() ? spec.output : output).c_str());
      return;
    }
    if (kind == "markers") {
      MarkerComparisonSpec spec = LoadMarkerComparison(spec_path, Registry::Global());
      if (seeds > 0) spec.seeds = seeds;
      folder = output.empty() ? spec.output : output;
      CheckReplaceable(folder, "comparison");  // before the work, not after it
      if (spec.seeds > 1) {  // every figure over seeds, with a recommendation
        const auto per_seed = CompareMarkersOverSeeds(spec, Registry::Global());
        table = MarkerSeedsMarkdown(spec, per_seed);
        csv = MarkerSeedsCsv(spec, per_seed);
      } else {
        const auto rows = CompareMarkers(spec, Registry::Global());
        table = MarkerTableMarkdown(spec, rows);
        csv = MarkerTableCsv(rows);
      }
    } else if (kind == "solvers") {
      SolverCompareSpec spec = LoadSolverCompare(spec_path, Registry::Global());
      if (seeds > 0) spec.seeds = seeds;
      folder = output.empty() ? spec.output : output;
      CheckReplaceable(folder, "comparison");
      const auto rows = RunSolverCompare(spec, Registry::Global());
      table = SolverCompareMarkdown(spec, rows);
      csv = SolverCompareCsv(rows);
    } else {
      CompareSpec spec = LoadCompareSpec(spec_path, Registry::Global());
      if (seeds > 0) spec.seeds = seeds;
      folder = output.empty() ? spec.output : output;
      CheckReplaceable(folder, "comparison");
      const auto rows = RunComparison(spec, Registry::Global());
      table = CompareTableMarkdown(spec, rows);
      csv = CompareTableCsv(rows);
    }
    StagedDirectory out(folder, "comparison");
    AtomicWriteFile(out.File("table.md"), table);
    AtomicWriteFile(out.File("table.csv"), csv);
    AtomicWriteFile(out.File(report::kReportFile),
                    report::CompareReportHtml(csv, table, "cellmetry compare: " + spec_path));
    out.Commit();
    std::printf("%s  written: %s/{table.md,table.csv,report.html}\n", table.c_str(), folder.c_str());
  });
}

}  // namespace cellmetry::app
