// CharucoTarget (charuco_target.h): OpenCV's board object, its corners in the target frame, and
// the printed squares and markers.
#include "charuco_target.h"

#include <cmath>

#include "fiducial_common/printed_page.h"

namespace cellmetry::charuco {
namespace {

// The black bit cells of marker `id` with its top-left corner at (u, v) on the page.
void AddMarker(const CharucoTarget& t, int id, double u, double v, fiducial::Page* page) {
  cv::Mat bits;
  cv::aruco::drawMarker(t.dictionary, id, t.cells(), bits, 1);  // one pixel per bit cell
  const double c = t.marker_mm / t.cells();
  for (int y = 0; y < t.cells(); ++y) {
    for (int x = 0; x < t.cells(); ++x) {
      if (bits.at<std::uint8_t>(y, x) < 128) {
        page->black.push_back({u + x * c, v + y * c, u + (x + 1) * c, v + (y + 1) * c});
      }
    }
  }
}

}  // namespace

cv::Ptr<cv::aruco::CharucoBoard> MakeBoard(const CharucoTarget& target) {
  return cv::aruco::CharucoBoard::create(target.squares_x, target.squares_y,
                                         static_cast<float>(target.square_mm),
                                         static_cast<float>(target.marker_mm), target.dictionary);
}

std::vector<MarkerPoint> Layout(const cv::aruco::CharucoBoard& board, double square_mm) {
  const double s = board.getSquareLength();
  std::vector<MarkerPoint> layout;
  for (size_t i = 0; i < board.chessboardCorners.size(); ++i) {
    const cv::Point3f& p = board.chessboardCorners[i];
    layout.push_back({static_cast<int>(i), Eigen::Vector3d(std::round(p.x / s) * square_mm,
                                                           std::round(p.y / s) * square_mm, 0.0)});
  }
  return layout;
}

std::vector<MarkerFace> Faces(const CharucoTarget& target, const cv::aruco::CharucoBoard& board,
                              double texels_per_mm) {
  const double s = target.square_mm, margin = s;
  const double width_mm = target.squares_x * s, height_mm = target.squares_y * s;
  // OpenCV's frame has x along the rows; whether its y runs down or up the board is read from a
  // marker's corners (top-left first, bottom-left last).
  const bool y_down = board.objPoints[0][3].y > board.objPoints[0][0].y;
  const double float_s = board.getSquareLength();
  fiducial::Page page;
  page.width_mm = width_mm + 2 * margin;
  page.height_mm = height_mm + 2 * margin;
  std::vector<bool> has_marker(target.squares_x * target.squares_y, false);
  const double inset = 0.5 * (s - target.marker_mm);
  for (size_t m = 0; m < board.ids.size(); ++m) {
    cv::Point3f centre(0, 0, 0);
    for (const cv::Point3f& p : board.objPoints[m]) centre += 0.25f * p;
    const int col = static_cast<int>(std::floor(centre.x / float_s));
    const int row_in_frame = static_cast<int>(std::floor(centre.y / float_s));
    const int row = y_down ? row_in_frame : target.squares_y - 1 - row_in_frame;
    has_marker[row * target.squares_x + col] = true;
    AddMarker(target, board.ids[m], margin + col * s + inset, margin + row * s + inset, &page);
  }
  for (int row = 0; row < target.squares_y; ++row) {
    for (int col = 0; col < target.squares_x; ++col) {
      if (has_marker[row * target.squares_x + col]) continue;
      page.black.push_back(
          {margin + col * s, margin + row * s, margin + (col + 1) * s, margin + (row + 1) * s});
    }
  }
  fiducial::Placement where;
  where.right = Eigen::Vector3d::UnitX();
  where.down = (y_down ? 1.0 : -1.0) * Eigen::Vector3d::UnitY();
  where.top_left = Eigen::Vector3d(-margin, y_down ? -margin : height_mm + margin, 0.0);
  return {fiducial::Print(
      page, where, fiducial::ChooseTexel(page, target.marker_mm / target.cells(), texels_per_mm))};
}

}  // namespace cellmetry::charuco
