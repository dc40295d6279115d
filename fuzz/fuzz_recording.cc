// Recording reader (recording.h, ReadRecording): a template recording folder (the first lines of
// VSB simulation B, with an images.csv), one of whose four files the fuzzed bytes replace.
// Input: first byte = which file (0 recording.yaml, 1 samples.csv, 2 observations.csv,
// 3 images.csv, modulo 4), the rest = that file's content.
#include <filesystem>
#include <map>
#include <string>

#include "cellmetry/formats/recording.h"
#include "fuzz_support.h"

namespace {

const char* const kFiles[] = {"recording.yaml", "samples.csv", "observations.csv", "images.csv"};

const std::map<std::string, std::string>& Template() {
  static const std::map<std::string, std::string> files = [] {
    const std::string sim_b = CELLMETRY_SOURCE_DIR "/tests/data/vsb/sim_b/";
    return std::map<std::string, std::string>{
        {"recording.yaml", cellmetry::fuzz::HeadLines(sim_b + "recording.yaml", 100)},
        {"samples.csv", cellmetry::fuzz::HeadLines(sim_b + "samples.csv", 6)},
        {"observations.csv", cellmetry::fuzz::HeadLines(sim_b + "observations.csv", 9)},
        {"images.csv", "sample,camera,view,path\n0,cam1,mono,images/0.png\n"}};
  }();
  return files;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string folder = cellmetry::fuzz::TempDir() + "/recording";
  static const bool made = std::filesystem::create_directories(folder);
  (void)made;
  const std::string chosen = kFiles[data[0] % 4];
  for (const auto& [name, text] : Template()) {
    if (name == chosen) {
      cellmetry::fuzz::WriteFile(folder + "/" + name, data + 1, size - 1);
    } else {
      cellmetry::fuzz::WriteFile(folder + "/" + name, text);
    }
  }
  cellmetry::fuzz::CheckContract([&] {
    const cellmetry::Recording recording = cellmetry::ReadRecording(folder);
    // What a caller does next: look samples up by the observations' ids.
    for (const auto& o : recording.observations) {
      const int index = recording.SampleIndex(o.sample);
      if (index < 0 || index >= static_cast<int>(recording.samples.size())) {
        cellmetry::fuzz::Violation("ReadRecording", "an observation names a missing sample");
      }
    }
  });
  return 0;
}
