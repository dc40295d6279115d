// Printed faces of dot markers: white disks on a black square, for Detector::Faces().
#pragma once

#include <Eigen/Core>
#include <vector>

#include "cellmetry/model/detector.h"

namespace cellmetry::dot {

// A black square of side `side_mm` centred on the target origin (face z out of the paper, as the
// target's) with white disks of `diameter_mm` at `centres_mm` (target x, y). Disk edges are
// anti-aliased (each texel holds its covered fraction), so the rendered edge is where the disk is
// and not on the texel grid. At least `texels_per_mm` texels per mm.
MarkerFace DiskFace(double side_mm, double diameter_mm,
                    const std::vector<Eigen::Vector2d>& centres_mm, double texels_per_mm);

}  // namespace cellmetry::dot
