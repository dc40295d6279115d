// ArucoTarget: what an `aruco` detector looks for, as printed: single markers or one grid board,
// and where their corners are in the target frame. Frames follow OpenCV 4.6 so that its pose
// functions return T_cam_target directly:
//
//   single markers  each marker in cv::aruco::estimatePoseSingleMarkers' frame (PatternPos
//                   CCW_center): centred on the origin, x right, y up, z out of the paper;
//                   top-left (-L/2, L/2, 0), top-right (L/2, L/2, 0), bottom-right (L/2, -L/2, 0),
//                   bottom-left (-L/2, -L/2, 0). Every listed id has the same corners: a target
//                   carries one of them (the ids tell markers apart, not where they are).
//   grid board      cv::aruco::GridBoard::create's objPoints as OpenCV 4.6 sets them: the
//                   top-left corner of the top-left marker at the origin, x right, y down the
//                   board, so z points into the paper; marker (col, row) is
//                   first_id + row * markers_x + col.
//
// Keypoint ids: marker_id * 4 + corner, corners in OpenCV's order (top-left, top-right,
// bottom-right, bottom-left of the marker as printed).
#pragma once

#include <opencv2/aruco.hpp>

#include <vector>

#include "cellmetry/model/detector.h"
#include "fiducial_common/printed_page.h"

namespace cellmetry::aruco {

struct ArucoTarget {
  cv::Ptr<cv::aruco::Dictionary> dictionary;
  double marker_length_mm = 0.0;
  // Single markers: the ids reported (in this order in layout()).
  std::vector<int> single_ids;
  // Grid board (markers_x > 0).
  int markers_x = 0;
  int markers_y = 0;
  double separation_mm = 0.0;
  int first_id = 0;

  bool board() const { return markers_x > 0; }
  std::vector<int> ids() const;
  // Bit cells per marker side, black border included (markerSize + 2).
  int cells() const { return dictionary->markerSize + 2; }
  double cell_mm() const { return marker_length_mm / cells(); }
};

std::vector<MarkerPoint> Layout(const ArucoTarget& target);

// The printed target: a board, or the first single marker, with a white margin of two bit cells
// (ArUco needs white around the black border to find its contour). Marker bits come from
// cv::aruco::drawMarker, so the texture shows exactly what OpenCV decodes.
std::vector<MarkerFace> Faces(const ArucoTarget& target, double texels_per_mm);

}  // namespace cellmetry::aruco
