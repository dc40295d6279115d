// Image reader (image.h, ReadGrayImage): the fuzzed bytes as an image file. OpenCV decodes by
// content, so one harness reaches every decoder the system's OpenCV has (PNG, JPEG, PxM, BMP, TIFF,
// ...). The contract: a GrayImage whose size matches its pixels, or InputError.
#include <string>

#include "cellmetry/formats/image.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = cellmetry::fuzz::TempDir() + "/image";
  cellmetry::fuzz::WriteFile(path, data, size);
  cellmetry::fuzz::CheckContract([&] {
    const cellmetry::GrayImage image = cellmetry::ReadGrayImage(path);
    if (image.width() <= 0 || image.height() <= 0) {
      cellmetry::fuzz::Violation("ReadGrayImage", "an image without pixels loaded");
    }
    // Touch the last pixel: the buffer must hold width x height.
    volatile std::uint8_t last = image.at(image.width() - 1, image.height() - 1);
    (void)last;
  });
  return 0;
}
