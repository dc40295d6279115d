// Dot marker faces (disk_texture.h): white disks on a black square, each texel holding the disk's
// covered fraction so that the edges are anti-aliased.
#include "dot_common/disk_texture.h"

#include <algorithm>
#include <cmath>

namespace cellmetry::dot {

MarkerFace DiskFace(double side_mm, double diameter_mm,
                    const std::vector<Eigen::Vector2d>& centres_mm, double texels_per_mm) {
  const int n = static_cast<int>(std::ceil(side_mm * std::max(texels_per_mm, 1.0)));
  MarkerFace face;
  face.mm_per_texel = side_mm / n;  // exactly n texels across: the square stays centred
  face.texture = GrayImage(n, n, 0);
  face.T_target_face.t = Eigen::Vector3d(-side_mm / 2, -side_mm / 2, 0.0);
  const double t = face.mm_per_texel, r = diameter_mm / 2;
  for (const Eigen::Vector2d& c : centres_mm) {
    // Texel i covers [i, i + 1) * t - side / 2 in target x.
    const Eigen::Vector2d lo = (c.array() - r - t + side_mm / 2) / t;
    const Eigen::Vector2d hi = (c.array() + r + t + side_mm / 2) / t;
    for (int j = std::max(0, static_cast<int>(lo.y()));
         j < std::min(n, static_cast<int>(hi.y()) + 1); ++j) {
      for (int i = std::max(0, static_cast<int>(lo.x()));
           i < std::min(n, static_cast<int>(hi.x()) + 1); ++i) {
        const Eigen::Vector2d p((i + 0.5) * t - side_mm / 2, (j + 0.5) * t - side_mm / 2);
        const double covered = std::clamp(0.5 - ((p - c).norm() - r) / t, 0.0, 1.0);
        std::uint8_t& texel = face.texture.at(i, j);
        texel =
            std::max<std::uint8_t>(texel, static_cast<std::uint8_t>(std::lround(255.0 * covered)));
      }
    }
  }
  return face;
}

}  // namespace cellmetry::dot
