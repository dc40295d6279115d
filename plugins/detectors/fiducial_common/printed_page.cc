// PrintedPage (printed_page.h): a texel size that puts every rectangle edge on a texel boundary,
// and the page printed into a MarkerFace texture by area coverage.
#include "printed_page.h"

#include <algorithm>
#include <cmath>

namespace cellmetry::fiducial {
namespace {

constexpr double kAligned = 1e-6;  // texels: closer than this to a boundary counts as on it

bool OnBoundary(double mm, double mm_per_texel) {
  const double texels = mm / mm_per_texel;
  return std::abs(texels - std::round(texels)) < kAligned;
}

bool AllAligned(const Page& page, double mm_per_texel) {
  if (!OnBoundary(page.width_mm, mm_per_texel) || !OnBoundary(page.height_mm, mm_per_texel)) {
    return false;
  }
  for (const Rect& r : page.black) {
    if (!OnBoundary(r.u0, mm_per_texel) || !OnBoundary(r.u1, mm_per_texel) ||
        !OnBoundary(r.v0, mm_per_texel) || !OnBoundary(r.v1, mm_per_texel)) {
      return false;
    }
  }
  return true;
}

// A coordinate in texels, snapped to the boundary it is within kAligned of.
double Texels(double mm, double mm_per_texel) {
  const double texels = mm / mm_per_texel;
  return std::abs(texels - std::round(texels)) < kAligned ? std::round(texels) : texels;
}

}  // namespace

double ChooseTexel(const Page& page, double cell_mm, double texels_per_mm) {
  const int k_min = std::max(1, static_cast<int>(std::ceil(cell_mm * texels_per_mm - kAligned)));
  for (int k = k_min; k <= 8 * k_min; ++k) {
    if (AllAligned(page, cell_mm / k)) return cell_mm / k;
  }
  return cell_mm / k_min;
}

MarkerFace Print(const Page& page, const Placement& where, double mm_per_texel) {
  const int width = static_cast<int>(std::ceil(Texels(page.width_mm, mm_per_texel)));
  const int height = static_cast<int>(std::ceil(Texels(page.height_mm, mm_per_texel)));
  MarkerFace face;
  face.mm_per_texel = mm_per_texel;
  face.texture = GrayImage(width, height, 255);
  // Row `row` of the page as printed (v down) is texture row height - 1 - row (y up). Rectangles
  // do not overlap, so subtracting each one's coverage is exact where edges sit on texel
  // boundaries and within one gray level where they do not.
  for (const Rect& r : page.black) {
    const double a0 = Texels(r.u0, mm_per_texel), a1 = Texels(r.u1, mm_per_texel);
    const double b0 = Texels(r.v0, mm_per_texel), b1 = Texels(r.v1, mm_per_texel);
    for (int row = std::max(0, static_cast<int>(std::floor(b0)));
         row < std::min(height, static_cast<int>(std::ceil(b1))); ++row) {
      const double oy = std::min(b1, row + 1.0) - std::max(b0, static_cast<double>(row));
      for (int col = std::max(0, static_cast<int>(std::floor(a0)));
           col < std::min(width, static_cast<int>(std::ceil(a1))); ++col) {
        const double ox = std::min(a1, col + 1.0) - std::max(a0, static_cast<double>(col));
        std::uint8_t& texel = face.texture.at(col, height - 1 - row);
        texel = static_cast<std::uint8_t>(std::max(0L, texel - std::lround(255.0 * ox * oy)));
      }
    }
  }
  const Eigen::Vector3d up = -where.down;
  face.T_target_face.R.col(0) = where.right;
  face.T_target_face.R.col(1) = up;
  face.T_target_face.R.col(2) = where.right.cross(up);
  face.T_target_face.t = where.top_left + where.down * (height * mm_per_texel);
  return face;
}

}  // namespace cellmetry::fiducial
