// TagBoard: the AprilTags an `apriltag_board` detector looks for, as printed: one flat grid, or
// grids on the faces of a cube (a 3D board, as the 2020 workcell paper mounts on the end
// effector), and where their corners are in the target frame.
//
//   flat grid   like OpenCV 4.6's cv::aruco::GridBoard: the top-left tag's top-left corner at
//               the origin, x right, y down the board, z into the paper; tag (col, row) is
//               first_id + row * tags_x + col.
//   cube        the target frame at the cube's centre. Each listed face carries a
//               tags_x x tags_y grid centred on it, ids from that face's first_id, printed so
//               that it reads upright from outside: on the side faces (+-x, +-y) "up" is +z;
//               on +z "up" is +y, on -z it is -y. The face's z (MarkerFace) points out of the
//               cube.
//
// Keypoint ids: tag_id * 4 + corner, corners of the tag's width_at_border square in OpenCV's
// order: top-left, top-right, bottom-right, bottom-left of the tag as printed. Tags are
// tag_size_mm wide at that square (AprilTag's own definition of the tag size).
#pragma once

#include <apriltag.h>

#include <string>
#include <vector>

#include "cellmetry/model/detector.h"

namespace cellmetry::apriltag_board {

enum class CubeSide { kPlusX, kMinusX, kPlusY, kMinusY, kPlusZ, kMinusZ };

// "+x", "-x", "+y", "-y", "+z", "-z".
const std::vector<std::string>& CubeSideNames();

struct CubeFace {
  CubeSide side = CubeSide::kPlusZ;
  int first_id = 0;
};

struct TagBoard {
  int width_at_border = 8;  // cells, from the family
  int total_width = 10;     // cells, from the family
  int tags_x = 1;
  int tags_y = 1;
  double tag_size_mm = 0.0;
  double spacing_mm = 0.0;  // gap between the width_at_border squares of neighbouring tags
  int first_id = 0;         // flat grid
  double cube_mm = 0.0;     // 0: a flat grid; else the cube's side
  std::vector<CubeFace> cube_faces;

  bool cube() const { return cube_mm > 0.0; }
  double cell_mm() const { return tag_size_mm / width_at_border; }
  // Printed cells outside the width_at_border square, per side.
  int outer_cells() const { return (total_width - width_at_border) / 2; }
  // One grid's extent between the outer corners of its width_at_border squares.
  double grid_width_mm() const { return tags_x * tag_size_mm + (tags_x - 1) * spacing_mm; }
  double grid_height_mm() const { return tags_y * tag_size_mm + (tags_y - 1) * spacing_mm; }
  std::vector<int> ids() const;
};

std::vector<MarkerPoint> Layout(const TagBoard& board);

// The printed faces: a flat grid with one cell of white paper around the printed tags, or one
// white cube face per listed side with its grid. Tag cells come from the family's code table
// (tag_pattern.h).
std::vector<MarkerFace> Faces(const TagBoard& board, const apriltag_family_t& family,
                              double texels_per_mm);

}  // namespace cellmetry::apriltag_board
