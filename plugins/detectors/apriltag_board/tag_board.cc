// TagBoard (tag_board.h): where each tag's corners lie in the target frame and the printed faces,
// for one flat grid or grids on a cube's faces.
#include "tag_board.h"

#include "fiducial_common/printed_page.h"
#include "tag_pattern.h"

namespace cellmetry::apriltag_board {
namespace {

// One grid of tags and the page it is printed on.
struct Sheet {
  int first_id = 0;
  Eigen::Vector3d origin;  // top-left corner of the top-left tag's width_at_border square
  Eigen::Vector3d right;   // as printed, seen from the printed side (target frame)
  Eigen::Vector3d down;
  double page_left_mm = 0,
         page_top_mm = 0;  // page's top-left corner from `origin`, along right / down
  double page_width_mm = 0, page_height_mm = 0;
};

// Right and up of each cube side as seen from outside; the outward normal is right x up.
void SideAxes(CubeSide side, Eigen::Vector3d* right, Eigen::Vector3d* up) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(),
                        z = Eigen::Vector3d::UnitZ();
  switch (side) {
    case CubeSide::kPlusX: *right = y, *up = z; break;
    case CubeSide::kMinusX: *right = -y, *up = z; break;
    case CubeSide::kPlusY: *right = -x, *up = z; break;
    case CubeSide::kMinusY: *right = x, *up = z; break;
    case CubeSide::kPlusZ: *right = x, *up = y; break;
    case CubeSide::kMinusZ: *right = x, *up = -y; break;
  }
}

std::vector<Sheet> Sheets(const TagBoard& b) {
  const double w = b.grid_width_mm(), h = b.grid_height_mm();
  if (!b.cube()) {
    // One white cell around the printed tags: every tag's border has paper on both sides.
    const double margin = (b.outer_cells() + 1) * b.cell_mm();
    return {{b.first_id, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(),
             Eigen::Vector3d::UnitY(), -margin, -margin, w + 2 * margin, h + 2 * margin}};
  }
  std::vector<Sheet> sheets;
  for (const CubeFace& face : b.cube_faces) {
    Eigen::Vector3d right = Eigen::Vector3d::UnitX(), up = Eigen::Vector3d::UnitY();
    SideAxes(face.side, &right, &up);
    const Eigen::Vector3d centre = right.cross(up) * (0.5 * b.cube_mm);
    Sheet s;
    s.first_id = face.first_id;
    s.right = right;
    s.down = -up;
    s.origin = centre - 0.5 * w * s.right - 0.5 * h * s.down;
    s.page_left_mm = -0.5 * (b.cube_mm - w);
    s.page_top_mm = -0.5 * (b.cube_mm - h);
    s.page_width_mm = s.page_height_mm = b.cube_mm;
    sheets.push_back(s);
  }
  return sheets;
}

}  // namespace

const std::vector<std::string>& CubeSideNames() {
  static const std::vector<std::string> names = {"+x", "-x", "+y", "-y", "+z", "-z"};
  return names;
}

std::vector<int> TagBoard::ids() const {
  std::vector<int> out;
  const int per_grid = tags_x * tags_y;
  if (!cube()) {
    for (int i = 0; i < per_grid; ++i) out.push_back(first_id + i);
    return out;
  }
  for (const CubeFace& face : cube_faces) {
    for (int i = 0; i < per_grid; ++i) out.push_back(face.first_id + i);
  }
  return out;
}

std::vector<MarkerPoint> Layout(const TagBoard& board) {
  std::vector<MarkerPoint> layout;
  const double s = board.tag_size_mm, pitch = board.tag_size_mm + board.spacing_mm;
  for (const Sheet& sheet : Sheets(board)) {
    for (int row = 0; row < board.tags_y; ++row) {
      for (int col = 0; col < board.tags_x; ++col) {
        const int id = sheet.first_id + row * board.tags_x + col;
        const Eigen::Vector3d tl =
            sheet.origin + col * pitch * sheet.right + row * pitch * sheet.down;
        const Eigen::Vector3d corners[4] = {
            tl, tl + s * sheet.right, tl + s * (sheet.right + sheet.down), tl + s * sheet.down};
        for (int k = 0; k < 4; ++k) layout.push_back({id * 4 + k, corners[k]});
      }
    }
  }
  return layout;
}

std::vector<MarkerFace> Faces(const TagBoard& board, const apriltag_family_t& family,
                              double texels_per_mm) {
  std::vector<MarkerFace> faces;
  const double cell = board.cell_mm(), pitch = board.tag_size_mm + board.spacing_mm;
  const int outer = board.outer_cells(), n = family.total_width;
  for (const Sheet& sheet : Sheets(board)) {
    fiducial::Page page;
    page.width_mm = sheet.page_width_mm;
    page.height_mm = sheet.page_height_mm;
    for (int row = 0; row < board.tags_y; ++row) {
      for (int col = 0; col < board.tags_x; ++col) {
        const std::vector<bool> black =
            TagBlackCells(family, sheet.first_id + row * board.tags_x + col);
        // The printed tag's top-left cell on the page (u right, v down from the page corner).
        const double u = -sheet.page_left_mm + col * pitch - outer * cell;
        const double v = -sheet.page_top_mm + row * pitch - outer * cell;
        for (int y = 0; y < n; ++y) {
          for (int x = 0; x < n; ++x) {
            if (black[static_cast<size_t>(y) * n + x]) {
              page.black.push_back(
                  {u + x * cell, v + y * cell, u + (x + 1) * cell, v + (y + 1) * cell});
            }
          }
        }
      }
    }
    fiducial::Placement where;
    where.right = sheet.right;
    where.down = sheet.down;
    where.top_left =
        sheet.origin + sheet.page_left_mm * sheet.right + sheet.page_top_mm * sheet.down;
    faces.push_back(fiducial::Print(page, where, fiducial::ChooseTexel(page, cell, texels_per_mm)));
  }
  return faces;
}

}  // namespace cellmetry::apriltag_board
