// Importer (import/importer.h, ImportRecording): the two bundled mappings with the first rows of
// their tables, one of whose files the fuzzed bytes replace.
//   - the ASTL tracker mapping: two CSV files joined by row, an 8-bit header, quaternions, per-row
//     uncertainties, a date-time column (configs/import/astl_calibration.yaml);
//   - the VSB spreadsheet mapping: one CSV, samples and poses by column, Euler angles in metres
//     and degrees (configs/import/vsb_exp_a_excerpt.yaml).
// Input: first byte = which file (modulo 5: 0 ASTL mapping, 1 its joints, 2 its tracker export,
// 3 VSB mapping, 4 its table), the rest = that file's content.
//
// Beyond the shared contract, what the importer accepts must be a recording cellmetry reads:
// written and read back (WriteRecording, ReadRecording), it loads. An import that a later `run`
// would refuse is a finding.
#include <filesystem>
#include <string>
#include <vector>

#include "cellmetry/basics/error.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/import/importer.h"
#include "fuzz_support.h"

namespace {

struct TemplateFile {
  std::string folder;  // "astl" or "vsb"
  std::string name;
  std::string text;
};

std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at)) {
    text.replace(at, from.size(), to);
    at += to.size();
  }
  return text;
}

const std::vector<TemplateFile>& Templates() {
  static const std::vector<TemplateFile> files = [] {
    const std::string source = CELLMETRY_SOURCE_DIR "/";
    const std::string astl = source + "tests/data/astl/calibration/";
    // The mappings whole (comments and all), their tables' paths made local.
    return std::vector<TemplateFile>{
        {"astl", "mapping.yaml",
         Replaced(cellmetry::fuzz::HeadLines(source + "configs/import/astl_calibration.yaml", 200),
                  "../../tests/data/astl/calibration/", "")},
        {"astl", "joints_deg.csv", cellmetry::fuzz::HeadLines(astl + "joints_deg.csv", 5)},
        {"astl", "leica.csv", cellmetry::fuzz::HeadLines(astl + "leica.csv", 5)},
        {"vsb", "mapping.yaml",
         cellmetry::fuzz::HeadLines(source + "configs/import/vsb_exp_a_excerpt.yaml", 200)},
        {"vsb", "vsb_exp_a_excerpt.csv",
         cellmetry::fuzz::HeadLines(source + "configs/import/vsb_exp_a_excerpt.csv", 8)},
    };
  }();
  return files;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::vector<TemplateFile>& templates = Templates();
  const TemplateFile& chosen = templates[data[0] % templates.size()];
  const std::string folder = cellmetry::fuzz::TempDir() + "/" + chosen.folder;
  std::filesystem::create_directories(folder);
  for (const TemplateFile& file : templates) {
    if (file.folder != chosen.folder) continue;
    if (file.name == chosen.name) {
      cellmetry::fuzz::WriteFile(folder + "/" + file.name, data + 1, size - 1);
    } else {
      cellmetry::fuzz::WriteFile(folder + "/" + file.name, file.text);
    }
  }
  const std::string written = cellmetry::fuzz::TempDir() + "/imported";
  std::filesystem::remove_all(written);
  cellmetry::Recording recording;
  if (!cellmetry::fuzz::CheckContract(
          [&] { recording = cellmetry::ImportRecording(folder + "/mapping.yaml"); })) {
    return 0;
  }
  try {
    cellmetry::WriteRecording(recording, written);
    (void)cellmetry::ReadRecording(written);
  } catch (const cellmetry::InputError& e) {
    cellmetry::fuzz::Violation("an imported recording that does not read back", e.what());
  }
  return 0;
}
