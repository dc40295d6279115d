// Gray image files (image.h): any image OpenCV decodes, read as 8-bit gray with an InputError for
// a missing, empty or corrupt file; PNGs written atomically.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "cellmetry/basics/error.h"
#include "cellmetry/formats/atomic_file.h"
#include "cellmetry/formats/image.h"

namespace cellmetry {

namespace {

// True when `bytes` start with the full signature of PNG, JPEG, TIFF, BMP or binary PGM/PPM, as
// the matching OpenCV codec checks it, so that codec (and no other) is the one imdecode picks.
bool IsCameraImageFormat(const std::vector<unsigned char>& bytes) {
  auto starts = [&](std::initializer_list<unsigned char> magic) {
    return bytes.size() >= magic.size() && std::equal(magic.begin(), magic.end(), bytes.begin());
  };
  // A netpbm header is "P5" or "P6" and then whitespace; without it OpenCV's PxM codec declines
  // the file and imdecode offers it to the next codec.
  const bool netpbm =
      (starts({'P', '5'}) || starts({'P', '6'})) && bytes.size() > 2 && std::isspace(bytes[2]) != 0;
  return starts({0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'}) || starts({0xFF, 0xD8, 0xFF}) ||
         starts({'I', 'I', 0x2A, 0x00}) || starts({'M', 'M', 0x00, 0x2A}) || starts({'B', 'M'}) ||
         netpbm;
}

// True when `bytes` carry DICOM's mark ("DICM" after a 128-byte preamble). GDCM's reader, which
// OpenCV links, aborts the process on malformed DICOM; such a file never reaches imdecode, whatever
// its first bytes say (found by fuzz_image: "P5" then a non-space, and "DICM" at 128).
bool HasDicomMark(const std::vector<unsigned char>& bytes) {
  static constexpr unsigned char kMark[] = {'D', 'I', 'C', 'M'};
  return bytes.size() >= 132 && std::equal(std::begin(kMark), std::end(kMark), bytes.begin() + 128);
}

}  // namespace

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
  // Only the formats a camera writes reach a decoder: OpenCV would otherwise hand any bytes to
  // every codec it links, and one of them (GDCM's DICOM reader) aborts on malformed input
  // (found by fuzz_image).
  if (!IsCameraImageFormat(bytes) || HasDicomMark(bytes)) {
    throw InputError(where,
                     "the image cannot be decoded: not a PNG, JPEG, TIFF, BMP or PGM/PPM file",
                     "Save the frame in one of these formats");
  }
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
