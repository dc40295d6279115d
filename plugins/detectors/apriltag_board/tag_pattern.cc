// One AprilTag's printed cells (tag_pattern.h): apriltag_to_image()'s layout, rebuilt from the
// family's code table.
#include "tag_pattern.h"

namespace cellmetry::apriltag_board {

std::vector<bool> TagBlackCells(const apriltag_family_t& family, int id) {
  const int n = family.total_width;
  std::vector<bool> black(static_cast<size_t>(n) * n, true);
  auto white = [&](int x, int y) {
    if (x >= 0 && y >= 0 && x < n && y < n) black[static_cast<size_t>(y) * n + x] = false;
  };
  const int ring = family.width_at_border + (family.reversed_border ? 0 : 2);
  const int ring_start = (n - ring) / 2;
  for (int i = 0; i < ring - 1; ++i) {
    white(ring_start + i, ring_start);
    white(n - 1 - ring_start, ring_start + i);
    white(ring_start + i + 1, n - 1 - ring_start);
    white(ring_start, ring_start + 1 + i);
  }
  const int border_start = OuterCells(family);
  const uint64_t code = family.codes[id];
  for (uint32_t i = 0; i < family.nbits; ++i) {
    if (code & (uint64_t{1} << (family.nbits - i - 1))) {
      // bit_x / bit_y are stored unsigned but may be negative (bits outside the border).
      white(static_cast<int>(family.bit_x[i]) + border_start,
            static_cast<int>(family.bit_y[i]) + border_start);
    }
  }
  return black;
}

}  // namespace cellmetry::apriltag_board
