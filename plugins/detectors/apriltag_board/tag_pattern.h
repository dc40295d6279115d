// The printed cells of one AprilTag, from the family's code table.
//
// Follows apriltag_to_image() of the AprilTag 3 library (apriltag.c): a total_width x
// total_width grid of cells, black by default; a one-cell white ring just inside the black
// border (reversed-border families such as tagStandard41h12 and tagCircle21h7) or just outside
// it (classic families such as tag36h11); data bit i (most significant first) white when set,
// at (bit_x[i], bit_y[i]) from the border's top-left cell. The library's own function is not
// used because Debian's libapriltag does not export image_u8_destroy, so its image could not be
// freed.
//
// The detection corners are the corners of the width_at_border square (the black border's outer
// edge; the white ring's outer edge for reversed borders), which is what tag_size_mm measures.
#pragma once

#include <apriltag.h>

#include <vector>

namespace cellmetry::apriltag_board {

// total_width^2 flags, row by row from the top-left cell as printed: true = black.
std::vector<bool> TagBlackCells(const apriltag_family_t& family, int id);

// Cells between the outer edge of the printed tag and the width_at_border square, per side.
inline int OuterCells(const apriltag_family_t& family) {
  return (family.total_width - family.width_at_border) / 2;
}

}  // namespace cellmetry::apriltag_board
