// Images: an 8-bit grayscale image (GrayImage) and the non-owning view every detector plugin
// receives (ImageView). Pixel (x, y) is column x, row y; OpenCV's convention: the centre of the
// top-left pixel is (0, 0).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace cellmetry {

struct ImageView {
  int width = 0;
  int height = 0;
  int stride = 0;  // bytes from one row to the next
  const std::uint8_t* data = nullptr;

  std::uint8_t at(int x, int y) const { return data[static_cast<size_t>(y) * stride + x]; }
  bool empty() const { return width <= 0 || height <= 0 || data == nullptr; }
};

class GrayImage {
 public:
  GrayImage() = default;
  GrayImage(int width, int height, std::uint8_t fill = 0)
      : width_(width), height_(height), pixels_(static_cast<size_t>(width) * height, fill) {}

  int width() const { return width_; }
  int height() const { return height_; }
  std::uint8_t& at(int x, int y) { return pixels_[static_cast<size_t>(y) * width_ + x]; }
  std::uint8_t at(int x, int y) const { return pixels_[static_cast<size_t>(y) * width_ + x]; }
  std::uint8_t* data() { return pixels_.data(); }
  const std::uint8_t* data() const { return pixels_.data(); }
  ImageView view() const { return {width_, height_, width_, pixels_.data()}; }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<std::uint8_t> pixels_;
};

// Reads any image OpenCV reads, converted to 8-bit gray. An unreadable, corrupt or empty file is
// an InputError naming it.
GrayImage ReadGrayImage(const std::string& path);

// Writes a PNG atomically (temporary file, then rename).
void WriteGrayImage(const GrayImage& image, const std::string& path);

}  // namespace cellmetry
