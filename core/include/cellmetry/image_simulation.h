// `cellmetry simulate` with images: render what a camera (mono) or a stereo rig sees of a
// detector plugin's marker for every sample (render.h), list them in images.csv, and keep the
// exact keypoints (keypoints_truth.csv: sample,camera,view,id,u,v) for scoring detectors.
//
// The `images:` section of a simulation spec:
//   images:
//     detector: {type: dot, diameter_mm: 10}   # whose Faces() are printed on the target
//     stereo: ../cameras/oakd.yaml              # or mono: calibration.yaml; default: OakDLikeRig()
//     render: {supersampling: 4, blur_sigma_px: 0.6, noise_sigma: 2, background: 60}
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cellmetry/config_node.h"
#include "cellmetry/recording.h"
#include "cellmetry/registry.h"
#include "cellmetry/render.h"
#include "cellmetry/stereo.h"

namespace cellmetry {

struct ImageRenderSpec {
  std::string detector_type;
  std::optional<ConfigNode> detector_config;
  std::optional<StereoRig> rig;        // stereo (default when neither is given: OakDLikeRig())
  std::optional<PinholeCamera> mono;
  RenderOptions render;
};

ImageRenderSpec ReadImageRenderSpec(const ConfigNode& images, Registry& registry);

struct SampleView {
  int sample = 0;
  Pose T_cam_target;   // the recording camera's frame (the left camera of a rig)
};

// Adds the images of `views` to recording->images (camera `camera`) and returns the writer that
// renders them (in parallel) into a recording folder, with keypoints_truth.csv; pass it to
// WriteRecording's write_extra.
std::function<void(const std::string&)> PlanImages(const ImageRenderSpec& spec,
                                                   const std::string& camera,
                                                   const std::vector<SampleView>& views,
                                                   unsigned seed, Registry& registry,
                                                   Recording* recording);

}  // namespace cellmetry
