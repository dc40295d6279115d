// What a recording's images show and what took them; shared by the renderer
// (image_simulation.h) and `cellmetry detect` (detection.h).
//
//   ImagingCamera  a recording camera as hardware: one calibrated camera (its images are the view
//                  "mono") or a stereo rig (views "left" and "right"; the recording camera's frame
//                  is the left camera's, as triangulation reports it).
//   TargetMarker   which detector plugin's marker is printed on a recording target: the renderer
//                  draws its Faces(), detect runs its Detect() and places its layout().
//
// YAML: a camera is {mono: calibration.yaml} or {stereo: rig.yaml} (camera.h, stereo.h); a marker
// is a detector block {type: <plugin>, <its options>}.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cellmetry/formats/config_node.h"
#include "cellmetry/imaging/stereo.h"
#include "cellmetry/model/camera.h"
#include "cellmetry/registry/registry.h"

namespace cellmetry {

struct ImagingCamera {
  std::optional<StereoRig> rig;
  std::optional<PinholeCamera> mono;

  std::vector<std::string> Views() const;
  bool HasView(const std::string& view) const;
  // The calibration of a view; `view` must be one of Views().
  const PinholeCamera& View(const std::string& view) const;
  // Maps the recording camera's frame into the view's (T_right_left for "right", else identity).
  Pose T_view_camera(const std::string& view) const;
};

// Reads the `mono:` or `stereo:` key of `node` (exactly one must be there; paths relative to the
// node's file). The caller checks the node's other keys.
ImagingCamera ReadImagingCamera(const ConfigNode& node);

struct TargetMarker {
  std::string target;
  std::string detector_type;
  std::optional<ConfigNode> detector_config;  // always set once read
  int origin_id = 0;  // stereo: the keypoint at the target's origin, when it has one
};

// `detector` is a detector block; the plugin is created once so that bad options fail before
// any work.
TargetMarker ReadTargetMarker(const std::string& target, const ConfigNode& detector,
                              Registry& registry);

}  // namespace cellmetry
