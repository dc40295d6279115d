// The rendering simulator's image formation: what a calibrated camera sees of printed marker
// faces placed in its frame.
//
//   1. each pixel is supersampled (S x S rays through sub-pixel positions, distortion removed
//      exactly, camera.h); each ray meets the nearest visible face and reads its texture
//      (bilinear); rays that miss see the background;
//   2. the light falls off linearly across the image (illumination gradient);
//   3. optics and sensor blur (Gaussian);
//   4. Gaussian noise and 8-bit quantisation.
// Only the faces' neighbourhoods are ray traced; the rest of the frame is background. The exact
// keypoints (ProjectLayout) are the ground truth a detector is scored against.
#pragma once

#include <random>
#include <vector>

#include "cellmetry/model/camera.h"
#include "cellmetry/model/detector.h"

namespace cellmetry {

struct RenderOptions {
  int supersampling = 4;       // rays per pixel side
  double background = 60.0;    // gray level where no face is seen
  double black = 25.0;         // gray level of texture value 0 under the centre's light
  double white = 225.0;        // gray level of texture value 255
  double blur_sigma_px = 0.6;  // Gaussian blur of optics and sensor (0: none)
  Eigen::Vector2d illumination_gradient = Eigen::Vector2d(0.10, -0.06);  // relative, per frame
  double noise_sigma = 2.0;                                              // gray levels
};

struct PlacedTarget {
  Pose T_cam_target;
  const std::vector<MarkerFace>* faces = nullptr;
};

// The noise-free image before quantisation, row-major floats (width x height).
std::vector<float> RenderIdeal(const PinholeCamera& camera,
                               const std::vector<PlacedTarget>& targets,
                               const RenderOptions& options);

// The sensor: Gaussian noise (options.noise_sigma) and 8-bit quantisation of an ideal image.
// Many noisy views of one scene cost one RenderIdeal and one SensorImage each; the draws
// from `rng` are those RenderView makes.
GrayImage SensorImage(const std::vector<float>& ideal, int width, int height,
                      const RenderOptions& options, std::mt19937& rng);

// RenderIdeal plus the sensor (SensorImage).
GrayImage RenderView(const PinholeCamera& camera, const std::vector<PlacedTarget>& targets,
                     const RenderOptions& options, std::mt19937& rng);

// The exact pixels of the layout's keypoints (ids kept); points behind the camera are skipped.
std::vector<Keypoint> ProjectLayout(const PinholeCamera& camera, const Pose& T_cam_target,
                                    const std::vector<MarkerPoint>& layout);

// Cramer-Rao bound (px, 1 sigma per image axis) for the image position of everything the
// targets show, moving together: F = sum over pixels of (dI/du)^2 / noise^2 with dI/du the ideal
// image's derivative under a shift of the whole picture. No unbiased estimator of a target's
// image position can beat it; a detector's keypoint that averages the whole marker approaches it.
Eigen::Vector2d ImageShiftCramerRao(const std::vector<float>& ideal, int width, int height,
                                    double noise_sigma);

}  // namespace cellmetry
