// PrintedPage: black rectangles on white paper, and the MarkerFace texture the renderer draws
// for it. The square-fiducial plugins (aruco, apriltag_board) print their bit cells with it, the
// board plugins (checkerboard, charuco) their squares, so that the texture and the plugin's
// layout() come from the same numbers.
//
// A page is described as printed and seen from its printed side: u to the right, v down, in mm
// from its top-left corner. Its placement in the target frame says where that corner is and
// which target directions "right" and "down" are; the face's z axis (right x up) then points
// out of the printed side, as the MarkerFace contract requires (detector.h).
#pragma once

#include <vector>

#include "cellmetry/model/detector.h"

namespace cellmetry::fiducial {

struct Rect {
  double u0 = 0, v0 = 0, u1 = 0, v1 = 0;  // mm, u0 < u1, v0 < v1
};

struct Page {
  double width_mm = 0.0;
  double height_mm = 0.0;
  std::vector<Rect> black;  // must not overlap
};

struct Placement {
  Eigen::Vector3d top_left = Eigen::Vector3d::Zero();  // target frame, mm
  Eigen::Vector3d right = Eigen::Vector3d::UnitX();    // unit vectors in the target frame
  Eigen::Vector3d down = Eigen::Vector3d::UnitY();
};

// The texel size (mm) for `page`: cell_mm / k with k the smallest integer such that texels are
// at most 1 / texels_per_mm and every rectangle edge and page side lies on a texel boundary
// (searched up to 8x finer). Aligned edges print exactly; when no such k exists the smallest k
// is returned and Print() anti-aliases the edges by area coverage.
double ChooseTexel(const Page& page, double cell_mm, double texels_per_mm);

// The face: texel value = 255 * (1 - black area fraction of the texel). The texture starts at
// the page's top-left corner; when the page is not a whole number of texels it extends past the
// right and bottom sides by less than one texel (white).
MarkerFace Print(const Page& page, const Placement& where, double mm_per_texel);

}  // namespace cellmetry::fiducial
