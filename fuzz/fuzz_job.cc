// Job reader (cell/job.h, LoadWorkcellJob): the fuzzed bytes as job.yaml in a folder that also
// holds the two bundled robot configs (ur3.yaml, delta.yaml) and a small recording (recording/,
// the first samples of VSB simulation B), so that a job naming them gets past the file checks.
// A job that loads is then checked against that recording (ValidateJobAgainstRecording), as
// `cellmetry run` does.
#include <filesystem>
#include <string>

#include "cellmetry/cell/job.h"
#include "cellmetry/formats/recording.h"
#include "fuzz_support.h"

namespace {

std::string folder;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  cellmetry::Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
  namespace fz = cellmetry::fuzz;
  folder = fz::TempDir() + "/job";
  std::filesystem::create_directories(folder + "/recording");
  fz::CopyFile(CELLMETRY_SOURCE_DIR "/configs/robots/ur3_vsb2020.yaml", folder + "/ur3.yaml");
  fz::CopyFile(CELLMETRY_SOURCE_DIR "/configs/robots/delta.yaml", folder + "/delta.yaml");
  const std::string sim_b = CELLMETRY_SOURCE_DIR "/tests/data/vsb/sim_b/";
  fz::CopyFile(sim_b + "recording.yaml", folder + "/recording/recording.yaml");
  fz::WriteFile(folder + "/recording/samples.csv", fz::HeadLines(sim_b + "samples.csv", 21));
  fz::WriteFile(folder + "/recording/observations.csv",
                fz::HeadLines(sim_b + "observations.csv", 41));
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const cellmetry::Recording recording = cellmetry::ReadRecording(folder + "/recording");
  // `plugin_paths:` dlopens every lib*.so of a folder the input names (say /usr/lib): that runs
  // other libraries' code, not the reader's. Left to test_bad_input (MissingPluginFolder) and
  // test_plugins.
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (text.find("plugin_paths") != std::string::npos) return 0;
  const std::string path = folder + "/job.yaml";
  cellmetry::fuzz::WriteFile(path, data, size);
  cellmetry::fuzz::CheckContract([&] {
    const cellmetry::WorkcellJob job =
        cellmetry::LoadWorkcellJob(path, cellmetry::Registry::Global(), false);
    cellmetry::ValidateJobAgainstRecording(job, recording);
  });
  return 0;
}
