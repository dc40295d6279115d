// `cellmetry simulate` with images: render what each camera (mono or stereo) sees of the markers
// on the simulation's targets for every sample (render.h), list them in images.csv, and keep the
// exact keypoints (keypoints_truth.csv: sample,camera,view,target,id,u,v) for scoring detectors.
//
// The `images:` section of a simulation spec (imaging.h for the blocks):
//   images:
//     detector: {type: dot, diameter_mm: 10}    # the marker on the simulation's one target, or
//     targets: {world: {type: apriltag_board, ...}, tool: {...}}   # a marker per target
//     stereo: ../cameras/oakd.yaml               # every camera (or mono: calibration.yaml), or
//     cameras: {cam1: {mono: ../cameras/cam1.yaml}, cam2: {...}}  # per camera
//     render: {supersampling: 4, blur_sigma_px: 0.6, noise_sigma: 2, background: 60}
// Without a camera calibration every camera is OakDLikeRig(). Every target a marker is printed
// on appears in every camera's images, hiding what lies behind it.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/imaging/imaging.h"
#include "cellmetry/imaging/render.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

struct ImageRenderSpec {
  std::vector<TargetMarker> markers;
  std::map<std::string, ImagingCamera> cameras;  // by recording camera
  RenderOptions render;
};

// `cameras` and `targets` are the simulation's; a section naming others is an InputError.
ImageRenderSpec ReadImageRenderSpec(const ConfigNode& images,
                                    const std::vector<std::string>& cameras,
                                    const std::vector<std::string>& targets, Registry& registry);

// What one recording camera sees at one sample: where each marked target is in its frame (the
// left camera's of a rig). Targets without a marker in the spec are ignored.
struct SampleView {
  int sample = 0;
  std::string camera;
  std::map<std::string, Pose> T_cam_target;
};

// Adds the images of `views` to recording->images and returns the writer that renders them (in
// parallel) into a recording folder, with keypoints_truth.csv; pass it to WriteRecording's
// write_extra.
std::function<void(const std::string&)> PlanImages(const ImageRenderSpec& spec,
                                                   const std::vector<SampleView>& views,
                                                   unsigned seed, Registry& registry,
                                                   Recording* recording);

}  // namespace cellmetry
