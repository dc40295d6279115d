// The 13-dot pattern's layout. The report's picture of its pattern (Porée 2023, figure 10) is not
// available; this one is the 5 x 5 grid's diamond |i| + |j| <= 2 at a pitch p:
//
//                 1                    target y up (the printed side facing the viewer,
//              2  3  4                 x to the right)
//           5  6  7  8  9              id 7 is the centre dot, at the target origin
//             10 11 12
//                13
//
// ids 1..13 row by row from the top (y = +2p) down, left to right. The diamond is point symmetric,
// so the mean of its dots is its centre (the report's centre), and its second moment is isotropic
// (sum i^2 = sum j^2 = 14, sum ij = 0), which the matcher uses. It is also symmetric under 90
// degree turns: ids are given with the target's x axis taken as the one nearest the image's +x.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace cellmetry::dot {

inline constexpr int kPatternDots = 13;

// (i, j) grid offsets of ids 1..13, in pitches (element k is id k + 1).
const std::vector<Eigen::Vector2d>& DiamondGrid();

}  // namespace cellmetry::dot
