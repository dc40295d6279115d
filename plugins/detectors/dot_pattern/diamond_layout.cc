// The 13-dot diamond (diamond_layout.h): the grid offsets |i| + |j| <= 2, row by row from the
// top, built once.
#include "diamond_layout.h"

#include <cstdlib>

namespace cellmetry::dot {

const std::vector<Eigen::Vector2d>& DiamondGrid() {
  static const std::vector<Eigen::Vector2d> grid = [] {
    std::vector<Eigen::Vector2d> g;
    for (int j = 2; j >= -2; --j) {
      for (int i = -2; i <= 2; ++i) {
        if (std::abs(i) + std::abs(j) <= 2) g.emplace_back(i, j);
      }
    }
    return g;
  }();
  return grid;
}

}  // namespace cellmetry::dot
