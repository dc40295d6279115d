// The 2023 report's Tables 3 and 4 for any set of detector plugins, on rendered stereo images:
//
//   repeatability  sigma of X, Y and depth of the triangulated target origin over `captures`
//                  renders of one static pose (new noise each time), beside its floor;
//   accuracy       mean and RMS distance to the true origin, over the workspace positions;
//   detection rate over `positions` random poses in the workspace (depth, lateral spread, tilt);
//   time per frame of the detector (one image).
// The floor is the Cramer-Rao bound of the target's image position in each view
// (ImageShiftCramerRao of the ideal render) propagated through the stereo geometry
// (Triangulate's covariance): no detector can be more repeatable on these images.
//
// Spec (YAML, `compare: markers`):
//   detectors: {<label>: <detector block>, ...}
//   stereo: rig.yaml                  # default: OakDLikeRig() (75 mm, 1280 x 800, f 880 px)
//   static_pose: {xyz: [0, 0, 450], rvec: [3.14159, 0, 0]}   # T_cam_target (left camera)
//   captures: 100
//   workspace: {positions: 125, depth_mm: [300, 600], lateral_mm: 120, tilt_rad: 0.35}
//   render: {noise_sigma: 2, blur_sigma_px: 0.6, supersampling: 4}
//   seed: 1
//   seeds: 10                         # repetitions (default 10): seed, seed + 1, ...; with more
//                                     # than one, each figure reads mean [95 % t-interval] and a
//                                     # recommendation says which detector (marker_seeds.cc)
//   output: <folder for markers.md and markers.csv>
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/imaging/render.h"
#include "cellmetry/imaging/stereo.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

struct MarkerComparisonSpec {
  std::vector<std::pair<std::string, ConfigNode>> detectors;  // label, detector block
  StereoRig rig = OakDLikeRig();
  Pose static_pose;
  int captures = 100;
  int positions = 125;
  Eigen::Vector2d depth_mm = Eigen::Vector2d(300, 600);
  double lateral_mm = 120.0;
  double tilt_rad = 0.35;
  RenderOptions render;
  unsigned seed = 1;
  int seeds = 10;
  std::string output;
  // The spec file's text, hashed: a checkpoint written under another spec is not reused.
  std::string fingerprint;
};

struct MarkerRow {
  std::string label;
  Eigen::Vector3d repeatability_mm = Eigen::Vector3d::Zero();  // sigma X, Y, depth
  Eigen::Vector3d floor_mm = Eigen::Vector3d::Zero();          // Cramer-Rao, same axes
  double static_bias_mm = 0.0;                                 // |mean - truth| at the static pose
  double workspace_rms_mm = 0.0;                               // over detected workspace positions
  int captures_found = 0;
  int positions_found = 0;
  int positions = 0;
  double ms_per_frame = 0.0;  // median detection time of one image
};

MarkerComparisonSpec LoadMarkerComparison(const std::string& path, Registry& registry);
std::vector<MarkerRow> CompareMarkers(const MarkerComparisonSpec& spec, Registry& registry);
std::string MarkerTableMarkdown(const MarkerComparisonSpec& spec,
                                const std::vector<MarkerRow>& rows);
std::string MarkerTableCsv(const std::vector<MarkerRow>& rows);

// The comparison once per seed (spec.seed + i, i < spec.seeds): [seed][detector]. With a
// `checkpoint` path, each seed's rows are written there as the seed ends (JSON, keyed by the
// spec's fingerprint and the seed) and seeds found there are not run again: an interrupted
// comparison resumes where it stopped. The caller removes the file once the tables are written.
std::vector<std::vector<MarkerRow>> CompareMarkersOverSeeds(const MarkerComparisonSpec& spec,
                                                            Registry& registry,
                                                            const std::string& checkpoint = "");
// Each detector's figures as mean [95 % t-interval] over the seeds, and one recommendation on
// the workspace RMS error and time per frame (solver_compare.h's Recommendation).
std::string MarkerSeedsMarkdown(const MarkerComparisonSpec& spec,
                                const std::vector<std::vector<MarkerRow>>& per_seed);
std::string MarkerSeedsCsv(const MarkerComparisonSpec& spec,
                           const std::vector<std::vector<MarkerRow>>& per_seed);

}  // namespace cellmetry
