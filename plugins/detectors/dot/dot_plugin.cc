// Registers the `dot` detector: the report's white dot on a black background, found with a
// sub-pixel ellipse fit to its 50 % edge crossings.
#include <cmath>

#include "cellmetry/registry/registry.h"
#include "dot_common/dot_finder_options.h"
#include "dot_detector.h"

namespace cellmetry::dot {
namespace {

DotDetectorOptions ReadOptions(const ConfigNode& config) {
  std::vector<std::string> keys = {"type", "diameter_mm", "perspective_correction", "dot_normal"};
  for (const auto& key : DotFinderKeys()) keys.push_back(key);
  config.ExpectKeys(keys);
  DotDetectorOptions o;
  o.diameter_mm =
      ReadPositive(config, "diameter_mm", o.diameter_mm, "Give the printed dot's diameter in mm");
  o.finder = ReadDotFinderOptions(config);
  o.camera = ReadOptionalCamera(config);
  o.perspective_correction = config.GetBool("perspective_correction", false);
  if (o.perspective_correction) {
    if (!o.camera) {
      throw config["perspective_correction"].Error(
          "needs the camera's intrinsics", "Add camera: <calibration file>, or set it to false");
    }
    if (!config.Has("dot_normal")) {
      throw config["perspective_correction"].Error(
          "needs dot_normal: one ellipse fits two tilts of the dot",
          "Add dot_normal: [x, y, z], the direction the printed side faces in the camera frame "
          "(e.g. [0, 0.34, -0.94] for a dot tilted 20 degrees about the camera's x axis)");
    }
  }
  if (config.Has("dot_normal")) {
    const auto v = config["dot_normal"].AsDoubles(3);
    o.dot_normal = Eigen::Vector3d(v[0], v[1], v[2]);
    if (!(o.dot_normal.norm() > 0.0)) {
      throw config["dot_normal"].Error(
          "must be a direction, not zero",
          "Give the direction the printed side faces in the camera frame, e.g. [0, 0, -1]");
    }
  }
  return o;
}

std::unique_ptr<Detector> Create(const ConfigNode& config) {
  return std::make_unique<DotDetector>(ReadOptions(config));
}

}  // namespace
}  // namespace cellmetry::dot

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.kind = cellmetry::PluginKind::kDetector;
  info.name = "dot";
  info.description = "white dot on a black square: ellipse fit to sub-pixel 50 % edge crossings";
  info.options = {
      {"diameter_mm", "mm", "10", "the printed dot's diameter (Faces(), perspective correction)"},
  };
  for (const auto& doc : cellmetry::dot::DotFinderOptionDocs()) info.options.push_back(doc);
  info.options.push_back({"perspective_correction", "", "false",
                          "report the image of the dot's centre, not the ellipse's (needs camera "
                          "and dot_normal)"});
  info.options.push_back({"dot_normal", "", "",
                          "[x, y, z]: roughly the way the printed side faces, camera frame; picks "
                          "one of the two tilts an ellipse allows"});
  registry->AddDetector(info, &cellmetry::dot::Create);
}
