// Registers the `dot_pattern` detector: the report's 13-dot pattern (a diamond of white dots on
// black), its centre and its dots by id.
#include "cellmetry/registry/registry.h"
#include "dot_common/dot_finder_options.h"
#include "dot_pattern_detector.h"

namespace cellmetry::dot {
namespace {

DotPatternOptions ReadOptions(const ConfigNode& config) {
  std::vector<std::string> keys = {"type",   "dot_diameter_mm",     "pitch_mm",
                                   "centre", "max_layout_error_px", "perspective_correction"};
  for (const auto& key : DotFinderKeys()) keys.push_back(key);
  config.ExpectKeys(keys);
  DotPatternOptions o;
  o.dot_diameter_mm = ReadPositive(config, "dot_diameter_mm", o.dot_diameter_mm,
                                   "Give the printed dots' diameter in mm");
  o.pitch_mm = ReadPositive(config, "pitch_mm", o.pitch_mm,
                            "Give the distance between neighbouring dots' centres in mm");
  if (o.pitch_mm < 1.5 * o.dot_diameter_mm) {
    throw config[config.Has("pitch_mm") ? "pitch_mm" : "dot_diameter_mm"].Error(
        "pitch_mm must be at least 1.5 x dot_diameter_mm",
        "Neighbouring dots need black between them for their edges to be found");
  }
  const std::string centre = config.GetString("centre", "homography");
  if (centre == "mean") {
    o.centre = PatternCentre::kMean;
  } else if (centre != "homography") {
    throw config["centre"].Error("unknown centre '" + centre + "'", "Use homography or mean");
  }
  o.max_layout_error_px =
      ReadPositive(config, "max_layout_error_px", o.max_layout_error_px, "Give pixels, e.g. 1");
  o.finder = ReadDotFinderOptions(config);
  o.camera = ReadOptionalCamera(config);
  o.perspective_correction = config.GetBool("perspective_correction", false);
  if (o.perspective_correction && !o.camera) {
    throw config["perspective_correction"].Error(
        "needs the camera's intrinsics", "Add camera: <calibration file>, or set it to false");
  }
  return o;
}

std::unique_ptr<Detector> Create(const ConfigNode& config) {
  return std::make_unique<DotPatternDetector>(ReadOptions(config));
}

}  // namespace
}  // namespace cellmetry::dot

CELLMETRY_PLUGIN_ENTRY(registry) {
  cellmetry::PluginInfo info;
  info.kind = cellmetry::PluginKind::kDetector;
  info.name = "dot_pattern";
  info.description = "13 white dots in a diamond on black: centre (id 0) and dots 1..13";
  info.options = {
      {"dot_diameter_mm", "mm", "6", "the printed dots' diameter"},
      {"pitch_mm", "mm", "12", "grid pitch of the diamond (5 x 5 grid, |i| + |j| <= 2)"},
      {"centre", "", "homography",
       "homography: the layout's origin mapped by the fitted homography (exact when tilted); "
       "mean: the report's mean of the dots (biased when tilted, 25 % less noisy when not)"},
      {"max_layout_error_px", "px", "1",
       "largest distance of a dot from where the fitted layout puts it"},
  };
  for (const auto& doc : cellmetry::dot::DotFinderOptionDocs()) info.options.push_back(doc);
  info.options.push_back({"perspective_correction", "", "false",
                          "correct each dot's ellipse centre to its circle's centre, with the "
                          "pattern's tilt (needs camera)"});
  registry->AddDetector(info, &cellmetry::dot::Create);
}
