// CheckerboardTarget (checkerboard_target.h): inner corners in the target frame, and the printed
// squares.
#include "checkerboard_target.h"

#include "fiducial_common/printed_page.h"

namespace cellmetry::checkerboard {

std::vector<MarkerPoint> Layout(const CheckerboardTarget& target) {
  std::vector<MarkerPoint> layout;
  for (int row = 0; row < target.corners_y; ++row) {
    for (int col = 0; col < target.corners_x; ++col) {
      layout.push_back({row * target.corners_x + col,
                        Eigen::Vector3d(col * target.square_mm, row * target.square_mm, 0.0)});
    }
  }
  return layout;
}

std::vector<MarkerFace> Faces(const CheckerboardTarget& target, double texels_per_mm) {
  const double s = target.square_mm, margin = s;
  const int squares_x = target.corners_x + 1, squares_y = target.corners_y + 1;
  fiducial::Page page;
  page.width_mm = squares_x * s + 2 * margin;
  page.height_mm = squares_y * s + 2 * margin;
  for (int row = 0; row < squares_y; ++row) {
    for (int col = 0; col < squares_x; ++col) {
      if ((row + col) % 2 != 0) continue;  // white: the top-left square is black
      page.black.push_back(
          {margin + col * s, margin + row * s, margin + (col + 1) * s, margin + (row + 1) * s});
    }
  }
  // The first inner corner is one square in from the board's top-left corner.
  fiducial::Placement where;
  where.right = Eigen::Vector3d::UnitX();
  where.down = Eigen::Vector3d::UnitY();
  where.top_left = Eigen::Vector3d(-s - margin, -s - margin, 0.0);
  return {fiducial::Print(page, where, fiducial::ChooseTexel(page, s, texels_per_mm))};
}

}  // namespace cellmetry::checkerboard
