// Imaging cameras and target markers (imaging.h): a camera's views (mono, or a rig's left and
// right) and the YAML readers of both.
#include "cellmetry/imaging/imaging.h"
#include "cellmetry/model/camera_file.h"

#include <algorithm>

namespace cellmetry {

std::vector<std::string> ImagingCamera::Views() const {
  if (mono) return {"mono"};
  return {"left", "right"};
}

bool ImagingCamera::HasView(const std::string& view) const {
  const auto views = Views();
  return std::find(views.begin(), views.end(), view) != views.end();
}

const PinholeCamera& ImagingCamera::View(const std::string& view) const {
  if (mono) return *mono;
  return view == "right" ? rig->right : rig->left;
}

Pose ImagingCamera::T_view_camera(const std::string& view) const {
  return rig && view == "right" ? rig->T_right_left : Pose::Identity();
}

ImagingCamera ReadImagingCamera(const ConfigNode& node) {
  if (node.Has("stereo") == node.Has("mono")) {
    throw node.Error("give exactly one of 'stereo:' (a rig) or 'mono:' (a camera)",
                     "e.g. {stereo: ../cameras/oakd.yaml} or {mono: ../cameras/cam1.yaml}");
  }
  ImagingCamera camera;
  if (node.Has("stereo")) {
    camera.rig = ReadStereoRig(node.ResolvePath(node["stereo"].AsString()));
  } else {
    camera.mono = ReadCamera(node.ResolvePath(node["mono"].AsString()));
  }
  return camera;
}

TargetMarker ReadTargetMarker(const std::string& target, const ConfigNode& detector,
                              Registry& registry) {
  TargetMarker marker;
  marker.target = target;
  marker.detector_type = detector["type"].AsString();
  marker.detector_config = detector;
  registry.CreateDetector(marker.detector_type, detector);
  return marker;
}

}  // namespace cellmetry
