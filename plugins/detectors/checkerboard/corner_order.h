// The checkerboard's corners in layout order, whatever order findChessboardCornersSB found them
// in.
//
// findChessboardCornersSB returns rows of corners_x corners, but may start at any of the four
// outer corners and may list the rows mirrored: the same board gives four orders. Two checks fix
// it to the layout's (checkerboard_target.h):
//   1. handedness  seen from its printed side, the board's x (along a row) and y (down the
//                  columns) turn clockwise in the image, as the image's own axes do (y down);
//                  the other way round, the rows are listed bottom-up and are reversed;
//   2. colour      the cell right-down of corner (col, row) is black when col + row is even; the
//                  mean gray level of the cells that should be black against those that should be
//                  white says whether the order is the board turned by 180 degrees, and if so it
//                  is reversed. This needs corners_x + corners_y odd (the plugin insists).
#pragma once

#include <opencv2/core.hpp>

#include <vector>

namespace cellmetry::checkerboard {

// Reorders `corners` (corners_x * corners_y of them, row by row) in place.
void ToLayoutOrder(const cv::Mat& gray, int corners_x, int corners_y,
                   std::vector<cv::Point2f>* corners);

}  // namespace cellmetry::checkerboard
