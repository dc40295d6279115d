// CheckerboardTarget: the printed checkerboard a `checkerboard` detector looks for, and where its
// inner corners are in the target frame.
//
// The board has (corners_x + 1) x (corners_y + 1) squares of square_mm, the top-left square black
// (as OpenCV's gen_pattern.py prints it), with one square of white paper around it
// (findChessboardCornersSB wants that margin). Target frame: the top-left inner corner at the
// origin, x along a row of corners_x corners, y down the board, z into the paper (the object
// points of OpenCV's calibration samples, and cv::aruco::GridBoard's frame in 4.6).
// Keypoint ids: row * corners_x + col, row by row from the top-left corner.
//
// One of corners_x and corners_y must be even and the other odd: only then does the board look
// different turned by 180 degrees (its top-left square is black, its bottom-right white), so
// that the corner order, and with it the pose, is the same in every image.
#pragma once

#include <vector>

#include "cellmetry/model/detector.h"

namespace cellmetry::checkerboard {

struct CheckerboardTarget {
  int corners_x = 0;  // inner corners per row
  int corners_y = 0;  // inner corners per column
  double square_mm = 0.0;

  int corners() const { return corners_x * corners_y; }
};

std::vector<MarkerPoint> Layout(const CheckerboardTarget& target);

// The printed board with its white margin (fiducial_common's printed page).
std::vector<MarkerFace> Faces(const CheckerboardTarget& target, double texels_per_mm);

}  // namespace cellmetry::checkerboard
