// ArucoTarget (aruco_target.h): its marker ids, where their corners lie in the target frame
// (OpenCV 4.6's frames), and the printed faces.
#include "aruco_target.h"

namespace cellmetry::aruco {
namespace {

// Where one marker lies: its top-left corner and its right / down directions (target frame).
struct MarkerPlace {
  int id = 0;
  Eigen::Vector3d top_left;
  Eigen::Vector3d right;
  Eigen::Vector3d down;
};

std::vector<MarkerPlace> Places(const ArucoTarget& t) {
  std::vector<MarkerPlace> places;
  if (!t.board()) {
    const double h = 0.5 * t.marker_length_mm;
    for (int id : t.single_ids) {
      places.push_back({id, {-h, h, 0}, Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitY()});
    }
    return places;
  }
  const double pitch = t.marker_length_mm + t.separation_mm;
  for (int row = 0; row < t.markers_y; ++row) {
    for (int col = 0; col < t.markers_x; ++col) {
      places.push_back({t.first_id + row * t.markers_x + col,
                        {col * pitch, row * pitch, 0.0},
                        Eigen::Vector3d::UnitX(),
                        Eigen::Vector3d::UnitY()});
    }
  }
  return places;
}

// The black bit cells of marker `id` with its top-left corner at (u, v) on the page.
void AddMarker(const ArucoTarget& t, int id, double u, double v, fiducial::Page* page) {
  cv::Mat bits;
  cv::aruco::drawMarker(t.dictionary, id, t.cells(), bits, 1);  // one pixel per bit cell
  const double c = t.cell_mm();
  for (int y = 0; y < t.cells(); ++y) {
    for (int x = 0; x < t.cells(); ++x) {
      if (bits.at<std::uint8_t>(y, x) < 128) {
        page->black.push_back({u + x * c, v + y * c, u + (x + 1) * c, v + (y + 1) * c});
      }
    }
  }
}

}  // namespace

std::vector<int> ArucoTarget::ids() const {
  if (!board()) return single_ids;
  std::vector<int> out;
  for (int i = 0; i < markers_x * markers_y; ++i) out.push_back(first_id + i);
  return out;
}

std::vector<MarkerPoint> Layout(const ArucoTarget& target) {
  std::vector<MarkerPoint> layout;
  const double L = target.marker_length_mm;
  for (const MarkerPlace& m : Places(target)) {
    const Eigen::Vector3d corners[4] = {m.top_left, m.top_left + L * m.right,
                                        m.top_left + L * (m.right + m.down),
                                        m.top_left + L * m.down};
    for (int k = 0; k < 4; ++k) layout.push_back({m.id * 4 + k, corners[k]});
  }
  return layout;
}

std::vector<MarkerFace> Faces(const ArucoTarget& target, double texels_per_mm) {
  const double margin = 2.0 * target.cell_mm();
  const double L = target.marker_length_mm;
  fiducial::Page page;
  fiducial::Placement where;
  if (target.board()) {
    const double pitch = L + target.separation_mm;
    page.width_mm = target.markers_x * pitch - target.separation_mm + 2 * margin;
    page.height_mm = target.markers_y * pitch - target.separation_mm + 2 * margin;
    for (int row = 0; row < target.markers_y; ++row) {
      for (int col = 0; col < target.markers_x; ++col) {
        AddMarker(target, target.first_id + row * target.markers_x + col, margin + col * pitch,
                  margin + row * pitch, &page);
      }
    }
    where.right = Eigen::Vector3d::UnitX();
    where.down = Eigen::Vector3d::UnitY();
    where.top_left = Eigen::Vector3d(-margin, -margin, 0.0);
  } else {
    page.width_mm = page.height_mm = L + 2 * margin;
    AddMarker(target, target.single_ids.front(), margin, margin, &page);
    where.right = Eigen::Vector3d::UnitX();
    where.down = -Eigen::Vector3d::UnitY();
    where.top_left = Eigen::Vector3d(-0.5 * L - margin, 0.5 * L + margin, 0.0);
  }
  return {
      fiducial::Print(page, where, fiducial::ChooseTexel(page, target.cell_mm(), texels_per_mm))};
}

}  // namespace cellmetry::aruco
