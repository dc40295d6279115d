// `cellmetry compare SPEC.yaml`: the report's Table 7 for any pose sets, sizes, formulations and
// solvers (kinematic_compare.h); writes table.md and table.csv.
#include <cstdio>

#include "cellmetry/atomic_file.h"
#include "cellmetry/kinematic_compare.h"
#include "cellmetry/progress.h"
#include "commands.h"

namespace cellmetry::app {

void AddCompareCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand(
      "compare", "calibrate simulated arms per pose set x size x formulation x solver (Table 7)");
  static std::string spec_path, output;
  cmd->add_option("spec", spec_path, "comparison spec (YAML, compare: kinematic)")->required();
  cmd->add_option("-o,--output", output, "folder for table.md and table.csv");
  cmd->callback([&context] {
    Progress::SetQuiet(context.quiet);
    LoadPlugins(context);
    const CompareSpec spec = LoadCompareSpec(spec_path, Registry::Global());
    const auto rows = RunComparison(spec, Registry::Global());
    const std::string table = CompareTableMarkdown(spec, rows);
    const std::string folder = output.empty() ? spec.output : output;
    StagedDirectory out(folder);
    AtomicWriteFile(out.File("table.md"), table);
    AtomicWriteFile(out.File("table.csv"), CompareTableCsv(rows));
    out.Commit();
    std::printf("%s  written: %s/{table.md,table.csv}\n", table.c_str(), folder.c_str());
  });
}

}  // namespace cellmetry::app
