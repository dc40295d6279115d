// `cellmetry import MAPPING.yaml -o FOLDER`: a user's table (CSV or JSON lines), or several
// joined row by row or by time, and a mapping file that says what their columns are
// (import_mapping.h) become a cellmetry recording, written
// whole or not at all, into a folder cellmetry may write (atomic_file.h).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/import/importer.h"
#include "commands.h"

namespace cellmetry::app {
namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string Count(size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

void Import(const std::string& mapping_path, const std::string& output) {
  CheckReplaceable(output, "recording");  // before the work, not after it
  const ImportMapping mapping = ReadImportMapping(mapping_path);
  const JoinedTable table = ReadMappedTables(mapping);
  const Recording recording = ImportTable(mapping, table);
  if (StopAfterCheck(output)) return;
  // The mapping goes with the recording, for whoever wonders where the numbers came from.
  const std::string provenance =
      "# The mapping this recording was imported with by `cellmetry import " + mapping_path +
      "`\n# (its table: relative to that file). Never read by cellmetry.\n" +
      ReadFile(mapping_path);
  WriteRecording(recording, output, "", [&](const std::string& staging) {
    AtomicWriteFile(staging + "/import.yaml", provenance);
  });
  std::set<int> poses;
  for (const auto& s : recording.samples) poses.insert(s.pose);
  std::printf("imported %s of %s: %s at %s, %s of %s by %s -> %s\n",
              Count(table.num_rows(), "row").c_str(), table.FileNames().c_str(),
              Count(recording.samples.size(), "sample").c_str(),
              Count(poses.size(), "pose").c_str(),
              Count(recording.observations.size(), "observation").c_str(),
              Count(recording.targets.size(), "target").c_str(),
              Count(recording.cameras.size(), "camera").c_str(), output.c_str());
}

}  // namespace

void AddImportCommand(CLI::App& app, Context& context) {
  CLI::App* cmd = app.add_subcommand(
      "import", "make a recording from your own table (CSV or JSON lines) and a mapping file");
  static std::string mapping_path, output;
  cmd->add_option("mapping", mapping_path,
                  "mapping file (YAML, mapping: cellmetry-import/1; see docs/formats.md)")
      ->required();
  cmd->add_option("-o,--output", output, "recording folder to write")->required();
  cmd->callback([&context] {
    (void)context;
    Import(mapping_path, output);
  });
}

}  // namespace cellmetry::app
