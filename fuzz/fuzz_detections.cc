// Detection log reader (imaging/detection.h, ReadDetectionLog): the fuzzed bytes as a recording's
// detections.jsonl, the resumable log `cellmetry detect` appends to and reads back on a rerun.
// What it returns is used as is by the rest of `detect` (sample ids, keypoint ids, pixels and
// their covariance), so a log that loads must hold only detections a run could have written.
#include <cmath>
#include <string>

#include "cellmetry/imaging/detection.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = cellmetry::fuzz::TempDir() + "/detections.jsonl";
  cellmetry::fuzz::WriteFile(path, data, size);
  cellmetry::fuzz::CheckContract([&] {
    for (const auto& d : cellmetry::ReadDetectionLog(path)) {
      if (d.sample < 0)
        cellmetry::fuzz::Violation("ReadDetectionLog", "a negative sample id loaded");
      for (const auto& k : d.detection.keypoints) {
        if (!k.pixel.allFinite() || !k.covariance_px2.allFinite()) {
          cellmetry::fuzz::Violation("ReadDetectionLog", "a keypoint that is not finite loaded");
        }
      }
    }
  });
  return 0;
}
