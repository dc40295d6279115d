// Corner refinement by edge lines, for square fiducials (ArUco markers, AprilTags).
//
// Why: corner detectors that look at the corner itself (cv::cornerSubPix, and the AprilTag
// library's quad fit) are pulled toward the inside of a blurred corner: on rendered views with a
// 0.6 px blur we measured 0.15-0.3 px per corner, the same sign for every draw, so it does not
// average out and it shrinks the marker (a scale, hence depth, bias in any pose from it). The
// sides of a marker are long straight edges; their intersections are unbiased.
//
// How: for each side, one scan across the edge per pixel row (or column) along its middle part
// (away from the corners, where the neighbouring side would be in the scan), along the pixel axis
// nearer the side's normal, and on each scan the edge by the area method: with plateau levels a
// (start) and b (end), a step at e gives integral of (I - a) / (b - a) over [-w, w] = w - e. The
// integral of a blurred step does not depend on the (symmetric) blur, and the trapezoid rule over
// pixel values integrates it almost independently of the pixel phase. A total-least-squares line
// through the edge points (once more without outliers) per side; corners are where neighbouring
// lines meet. The first pass assumes a 2 px blur reach, measures the ramp width sigma and centres
// the scans; up to two more use bands 2.5 sigma short of the next edge.
//
// When not to: the scan must not see the next edge (inside a marker, the border cell's inner edge
// one cell away), so the band is set from the quad's size (cells across a side). On small, blurred
// or sharpened markers (OpenCV's tutorial photographs: 4-6 px cells, sigma ~1 px, halos) no band
// holds a clean step: there the crossing moves when the scans are cut to 0.6 of their length
// (0.2-0.4 px on those photographs; under 0.035 px on our rendered views), and a marker whose
// edges move more than 0.1 px is left as it was (kTooSmall). Lines are straight in the image:
// lens distortion bends long edges (use undistorted images or markers small in the frame).
#pragma once

#include <array>

#include "cellmetry/basics/transform.h"
#include "cellmetry/formats/image.h"

namespace cellmetry::fiducial {

using Quad = std::array<Eigen::Vector2d, 4>;  // corners in order around the square, OpenCV pixels

enum class EdgeRefinement {
  kRefined,   // the quad now has the lines' corners
  kTooSmall,  // cells too narrow for the image's blur (no scan holds a clean step without seeing
              // the next edge): left as it was; corner-based refinement fails there too
  kFailed,    // too few clean edge points (off the image, low contrast, occluded): left as it was
};

// Refines `quad` in place. `cells`: bit cells across a side of the detected square (its black
// border included); `clear_cells`: how many cells on either side of an edge hold no other edge
// (1 for a one-cell border with at least a cell of paper around it).
EdgeRefinement RefineByEdgeLines(const ImageView& image, int cells, double clear_cells, Quad* quad);

}  // namespace cellmetry::fiducial
