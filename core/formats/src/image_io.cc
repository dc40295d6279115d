// Gray image files (image.h): any image OpenCV decodes, read as 8-bit gray with an InputError for
// a missing, empty or corrupt file; PNGs written atomically.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/basics/error.h"
#include "cellmetry/formats/image.h"

namespace cellmetry {

GrayImage ReadGrayImage(const std::string& path) {
  const SourceLocation where{path, 0, 0};
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError(where, "image not found", "Check the path in images.csv (relative to it)");
  }
  // Read the bytes ourselves: imread cannot tell a missing file from a corrupt one.
  std::ifstream in(path, std::ios::binary);
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  if (bytes.empty()) throw InputError(where, "the image file is empty", "Re-export the image");
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
    decoded.release();
  }
  if (decoded.empty() || decoded.depth() != CV_8U) {
    throw InputError(where, "the image cannot be decoded (corrupt, or not an image)",
                     "Re-export it as PNG or JPEG");
  }
  GrayImage image(decoded.cols, decoded.rows);
  for (int y = 0; y < decoded.rows; ++y) {
    std::copy(decoded.ptr<std::uint8_t>(y), decoded.ptr<std::uint8_t>(y) + decoded.cols,
              image.data() + static_cast<size_t>(y) * decoded.cols);
  }
  return image;
}

void WriteGrayImage(const GrayImage& image, const std::string& path) {
  const cv::Mat view(image.height(), image.width(), CV_8UC1,
                     const_cast<std::uint8_t*>(image.data()));
  std::vector<unsigned char> png;
  cv::imencode(".png", view, png);
  AtomicWriteFile(path, std::string(png.begin(), png.end()));
}

}  // namespace cellmetry
