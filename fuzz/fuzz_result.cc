// Result reader (exports/calibrated_cell.h, ReadCalibratedCell): the fuzzed bytes as result.json
// in a result folder, read as `cellmetry export` and `cellmetry compensate` read it: typed by
// ReadWorkcellResult, then each recorded robot model and effect rebuilt through the registry
// (plugins loaded). What loads must be usable: every robot with its model and one value per
// model parameter, the covariance square over the free parameters and finite.
#include <filesystem>
#include <string>

#include "cellmetry/exports/calibrated_cell.h"
#include "cellmetry/registry/registry.h"
#include "fuzz_support.h"

namespace {

std::string folder;

bool Usable(const cellmetry::CalibratedCell& cell) {
  for (const auto& robot : cell.robots) {
    if (!robot.model || robot.values.size() != robot.model->parameters().size()) {
      return false;
    }
  }
  const auto& c = cell.covariance;
  const auto n = static_cast<Eigen::Index>(c.names.size());
  const bool square =
      c.covariance.size() == 0 || (c.covariance.rows() == n && c.covariance.cols() == n);
  return square && c.covariance.allFinite();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  cellmetry::Registry::Global().LoadFolder(CELLMETRY_PLUGIN_DIR);
  folder = cellmetry::fuzz::TempDir() + "/result";
  std::filesystem::create_directories(folder);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  cellmetry::fuzz::WriteFile(folder + "/result.json", data, size);
  cellmetry::fuzz::CheckContract([&] {
    const cellmetry::CalibratedCell cell =
        cellmetry::ReadCalibratedCell(folder, cellmetry::Registry::Global());
    if (!Usable(cell)) {
      cellmetry::fuzz::Violation("ReadCalibratedCell", "a result that cannot be used loaded");
    }
  });
  return 0;
}
