// CharucoTarget: the ChArUco board a `charuco` detector looks for, as OpenCV 4.6 contrib's
// cv::aruco::CharucoBoard::create makes it, and where its chessboard corners are in the target
// frame.
//
// squares_x x squares_y squares of square_mm, the top-left one black; every white square holds
// an ArUco marker of marker_mm, centred, ids 0, 1, ... in the order CharucoBoard::create gives
// them. Target frame and keypoints are OpenCV's, taken from the board object itself so that its
// pose functions would return the same T_cam_target: a keypoint's id is the index of its
// chessboard corner in CharucoBoard::chessboardCorners (the inner corners, row by row from the
// top-left one), and layout() puts it there (snapped to the exact multiple of square_mm that
// OpenCV stores as a float).
#pragma once

#include <opencv2/aruco/charuco.hpp>

#include <vector>

#include "cellmetry/model/detector.h"

namespace cellmetry::charuco {

struct CharucoTarget {
  cv::Ptr<cv::aruco::Dictionary> dictionary;
  int squares_x = 0;
  int squares_y = 0;
  double square_mm = 0.0;
  double marker_mm = 0.0;

  // White squares, each with a marker (the top-left square is black).
  int markers() const { return squares_x * squares_y / 2; }
  // Bit cells per marker side, black border included (markerSize + 2).
  int cells() const { return dictionary->markerSize + 2; }
};

cv::Ptr<cv::aruco::CharucoBoard> MakeBoard(const CharucoTarget& target);

std::vector<MarkerPoint> Layout(const cv::aruco::CharucoBoard& board, double square_mm);

// The printed board with one square of white paper around it. Squares without a marker are
// black; marker bits come from cv::aruco::drawMarker, so the texture shows what OpenCV decodes.
std::vector<MarkerFace> Faces(const CharucoTarget& target, const cv::aruco::CharucoBoard& board,
                              double texels_per_mm);

}  // namespace cellmetry::charuco
