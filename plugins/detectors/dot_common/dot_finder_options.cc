// The options both dot detectors share (dot_finder_options.h): their documentation, and reading
// them from YAML with an InputError for a value out of range.
#include "dot_common/dot_finder_options.h"

#include <string>

namespace cellmetry::dot {

std::vector<std::string> DotFinderKeys() {
  return {"gamma",        "threshold",      "min_area_px", "max_area_px", "min_circularity",
          "min_contrast", "max_fit_rms_px", "edge",        "camera"};
}

std::vector<OptionDoc> DotFinderOptionDocs() {
  const DotFinderOptions d;
  auto number = [](double v) {
    std::string s = std::to_string(v);
    s.erase(s.find_last_not_of('0') + 1);
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
  };
  return {
      {"gamma", "", number(d.gamma),
       "gray levels become 255 (level / 255)^gamma before thresholding and edge location; 1 = "
       "none"},
      {"threshold", "gray level", "auto",
       "global threshold (after gamma) above which the dots are white blobs; auto = halfway "
       "between the median and the brightest dot-sized area (give a level if most of the frame "
       "is bright)"},
      {"min_area_px", "px", number(d.filter.min_area_px),
       "smallest blob (pixel count) kept as a dot"},
      {"max_area_px", "px", number(d.filter.max_area_px),
       "largest blob (pixel count) kept as a dot"},
      {"min_circularity", "", number(d.filter.min_circularity),
       "4 pi area / perimeter^2 of the blob's contour below which it is not a dot (1 = disk)"},
      {"min_contrast", "gray level", number(d.min_contrast),
       "least difference between a dot's white and the black around it"},
      {"max_fit_rms_px", "px", number(d.max_fit_rms_px),
       "largest RMS distance of a dot's sub-pixel edge points to their ellipse"},
      {"edge", "", "profile",
       "sub-pixel edge: profile = blurred step fitted across each crossing (no pixel locking); "
       "linear = the 50 % crossing by linear interpolation"},
      {"camera", "", "",
       "calibration file (our YAML or OpenCV's): edges are undistorted before the ellipse fit"},
  };
}

double ReadPositive(const ConfigNode& config, const std::string& key, double fallback,
                    const std::string& hint) {
  const double value = config.GetDouble(key, fallback);
  if (!(value > 0.0)) throw config[key].Error("must be positive", hint);
  return value;
}

DotFinderOptions ReadDotFinderOptions(const ConfigNode& config) {
  DotFinderOptions o;
  o.gamma = ReadPositive(config, "gamma", o.gamma, "Give an exponent such as 0.5 or 1 (none)");
  if (config.Has("threshold")) {
    const ConfigNode node = config["threshold"];
    const std::string text = node.AsString();
    if (text != "auto") {
      const double level = node.AsDouble();
      if (!(level >= 0.0 && level < 255.0)) {
        throw node.Error("must be a gray level from 0 to 254, or auto",
                         "Give the level between the dots' white and the background");
      }
      o.threshold = level;
    }
  }
  o.filter.min_area_px = config.GetDouble("min_area_px", o.filter.min_area_px);
  o.filter.max_area_px = config.GetDouble("max_area_px", o.filter.max_area_px);
  if (!(o.filter.min_area_px >= 6.0)) {
    throw config["min_area_px"].Error("must be at least 6 px",
                                      "An ellipse needs a few pixels of outline");
  }
  if (!(o.filter.max_area_px > o.filter.min_area_px)) {
    throw config[config.Has("max_area_px") ? "max_area_px" : "min_area_px"].Error(
        "max_area_px must be above min_area_px");
  }
  o.filter.min_circularity = config.GetDouble("min_circularity", o.filter.min_circularity);
  if (!(o.filter.min_circularity >= 0.0 && o.filter.min_circularity <= 1.0)) {
    throw config["min_circularity"].Error("must be between 0 and 1",
                                          "0.8 keeps dots seen up to about 50 degrees of tilt");
  }
  o.min_contrast =
      ReadPositive(config, "min_contrast", o.min_contrast, "Give gray levels, e.g. 40");
  o.max_fit_rms_px =
      ReadPositive(config, "max_fit_rms_px", o.max_fit_rms_px, "Give pixels, e.g. 0.3");
  const std::string edge = config.GetString("edge", "profile");
  if (edge == "linear") {
    o.edge = EdgeMethod::kLinear;
  } else if (edge != "profile") {
    throw config["edge"].Error("unknown edge method '" + edge + "'", "Use profile or linear");
  }
  return o;
}

std::optional<PinholeCamera> ReadOptionalCamera(const ConfigNode& config) {
  if (!config.Has("camera")) return std::nullopt;
  return ReadCamera(config.ResolvePath(config["camera"].AsString()));
}

}  // namespace cellmetry::dot
