// Camera calibration files (model/camera_file.h, ReadCamera): the fuzzed bytes as a camera file
// in any of its three formats (ours, OpenCV's FileStorage YAML or XML, ROS camera_info). What
// loads must be a camera a projection can use: a positive image size, positive finite focal
// lengths, a finite principal point and distortion.
#include <cmath>
#include <string>

#include "cellmetry/model/camera_file.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = cellmetry::fuzz::TempDir() + "/camera.yaml";
  cellmetry::fuzz::WriteFile(path, data, size);
  cellmetry::fuzz::CheckContract([&] {
    const cellmetry::PinholeCamera camera = cellmetry::ReadCamera(path);
    bool finite = std::isfinite(camera.cx) && std::isfinite(camera.cy);
    for (const double k : camera.distortion) finite = finite && std::isfinite(k);
    if (camera.width <= 0 || camera.height <= 0 || !(camera.fx > 0) || !(camera.fy > 0) ||
        !std::isfinite(camera.fx) || !std::isfinite(camera.fy) || !finite) {
      cellmetry::fuzz::Violation("ReadCamera", "a camera that cannot project loaded");
    }
  });
  return 0;
}
